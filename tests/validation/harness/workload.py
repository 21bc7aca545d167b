"""Case functions for the executor tests, in a module of their own: workers import it cheaply to run them."""

import os


def square_and_pid(x):
    """(x^2, the id of the process that computed it)."""
    return x * x, os.getpid()


def reciprocal(x):
    """1 / x: raises ZeroDivisionError at 0."""
    return 1.0 / x


def environment(name):
    """The value of an environment variable in the process that runs this (None when unset)."""
    return os.environ.get(name)
