"""Library statuses as Python exceptions carrying the library's message."""


class Error(Exception):
    """A treetrace call failed; str() is the library's message, .status the
    tt_status code, .status_name its short description."""

    status = None

    def __init__(self, message, status=None, status_name=""):
        super().__init__(message)
        if status is not None:
            self.status = status
        self.status_name = status_name


class InvalidArgumentError(Error, ValueError):
    status = 1


class OutOfMemoryError(Error, MemoryError):
    status = 2


class FileError(Error, OSError):
    """TT_ERR_IO: a file could not be opened, read or written."""
    status = 3


class ParseError(Error):
    status = 4


class UnsupportedError(Error):
    status = 5


class NoDeviceError(Error):
    status = 6


class InvariantError(Error):
    status = 7


class InternalError(Error):
    status = 8


_BY_STATUS = {cls.status: cls for cls in (InvalidArgumentError, OutOfMemoryError, FileError,
                                          ParseError, UnsupportedError, NoDeviceError,
                                          InvariantError, InternalError)}


def error_for(status, message, status_name=""):
    cls = _BY_STATUS.get(status, Error)
    err = cls(message, status, status_name)
    if not isinstance(err, OSError):
        return err
    # OSError's constructor takes (errno, strerror): keep the message whole.
    err.args = (message,)
    err.strerror = message
    return err
