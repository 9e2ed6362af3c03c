#pragma once
/// The rules the numbers of run options follow (solver tolerances, times, counts), one function
/// per rule, shared by the command line (as CLI11 validators) and the Python module (which applies
/// them to its arguments): both refuse the same values with the same words.

#include <string>

namespace CLI {
class Validator;
} // namespace CLI

namespace thermnet::app {

/// A rule: empty when `value` follows it, else what it must be ("a number from 1e-12 to 0.1").
using NumberRule = std::string (*)(double value);

/// A relative tolerance: from 1e-12 to 0.1.
std::string relative_tolerance_rule(double value);
/// An absolute tolerance: from 1e-12 to 10 K.
std::string absolute_tolerance_rule(double value);
/// A finite number above 0 (a time in s, an acceptance limit).
std::string positive_number_rule(double value);
/// A finite number from 0 (a floor in K that may be turned off with 0).
std::string non_negative_number_rule(double value);
/// A whole number above 0 (a count of samples, of findings).
std::string positive_whole_rule(double value);
/// A whole number from 2 (a count of validation folds).
std::string at_least_two_whole_rule(double value);
/// A whole number from 0 (a seed, a number of threads with 0 for all cores).
std::string non_negative_whole_rule(double value);

/// A CLI11 validator reading the option's text as a number and applying `rule`; `type_name` is
/// shown in the help (NUMBER, INT).
CLI::Validator rule_validator(NumberRule rule, const std::string& type_name);

/// A CLI11 validator of an output's file name: refuses an empty one (`--html ''` would otherwise
/// write nothing and say nothing).
CLI::Validator output_file_validator();

/// Throws std::invalid_argument naming `name` when `rule` refuses `value`.
void require(NumberRule rule, double value, const std::string& name);

} // namespace thermnet::app
