"""The Python layer's bad-argument error, shaped as the native module's: a ``ValueError`` whose
``argument`` attribute names the argument (the guide's "Errors")."""


def argument_error(argument: str, message: str) -> ValueError:
    """A ``ValueError`` with the message ``"{argument}: {message}"`` and ``argument`` set."""
    error = ValueError(f"{argument}: {message}")
    error.argument = argument  # type: ignore[attr-defined]
    return error
