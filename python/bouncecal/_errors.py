"""The exceptions the module raises: the C++ library's bouncecal::Error family, one to one.

Each carries the library's one-line message (what went wrong, which file or value, what to do),
the same text the command line prints after "bouncecal: error:". ``exit_status`` is the status
the command line exits with for the same problem (README, exit status).
"""


class Error(Exception):
    """Any problem a user can fix (bouncecal::Error)."""

    exit_status = 3


class InputError(Error, ValueError):
    """An input file or input data that cannot be read or does not hold what it should
    (bouncecal::InputError)."""

    exit_status = 2


class ConfigError(Error, ValueError):
    """A parameter or option outside its valid range (bouncecal::ConfigError)."""

    exit_status = 3


class OutputError(Error, OSError):
    """An output that cannot be written (bouncecal::OutputError)."""

    exit_status = 4


class CheckFailedError(Error):
    """A check that ran and did not pass, e.g. an engine's bounces that miss the card's
    restitution (bouncecal::CheckFailedError)."""

    exit_status = 5
