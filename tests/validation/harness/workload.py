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


def threads(_):
    """(Hessian threads, the largest thread count of a BLAS or MKL loaded here) in the process that runs this."""
    from threadpoolctl import threadpool_info

    from deformable.algebra.solvers import available, make_solver
    from deformable.physics.integrand import hessian_threads

    if "pardiso" in available():
        make_solver("pardiso")  # MKL loaded here, if this process had not yet
    return hessian_threads(), max(p["num_threads"] for p in threadpool_info())
