"""THERMNET_TEST_TIMEOUT_SCALE: the factor on the time limits of tests that bound their own runs.

A whole number from 1 to 9999 written without leading zeros, as CMake's math() and the shell
tests' arithmetic need it (bash reads 012 as octal, and wraps a number past 2^63); unset or empty
is 1, as in the shell tests. scripts/asan-suite sets 10 for the sanitized build; anything else
stops the test with a message naming the value.
"""
import os
import re
import sys


def timeout_scale() -> int:
    """The factor from the environment (1 when unset); exits with a message when it is not a
    positive integer."""
    value = os.environ.get("THERMNET_TEST_TIMEOUT_SCALE") or "1"
    if not re.fullmatch(r"[1-9][0-9]{0,3}", value, re.ASCII):
        sys.exit(f"THERMNET_TEST_TIMEOUT_SCALE={value!r}: expected a whole number from 1 to 9999 (a factor on time limits)")
    return int(value)
