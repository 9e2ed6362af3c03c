"""THERMNET_TEST_TIMEOUT_SCALE: the factor on the time limits of tests that bound their own runs.

A positive integer, as CMake's math() and the shell tests' arithmetic need it (scripts/asan-suite
sets 10 for the sanitized build); anything else stops the test with a message naming the value.
"""
import os
import sys


def timeout_scale() -> int:
    """The factor from the environment (1 when unset); exits with a message when it is not a
    positive integer."""
    value = os.environ.get("THERMNET_TEST_TIMEOUT_SCALE", "1")
    if not (value.isascii() and value.isdigit()) or int(value) < 1:
        sys.exit(f"THERMNET_TEST_TIMEOUT_SCALE={value!r}: expected a positive integer (a factor on time limits)")
    return int(value)
