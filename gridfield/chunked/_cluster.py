"""Connecting to a Dask scheduler with one clear error when it cannot be reached."""

from __future__ import annotations

from typing import Any

from ..core.errors import GridfieldError, ParameterError, shorten

__all__ = ["connect"]


def connect(address: str, *, timeout: float = 10.0) -> Any:
    """A ``distributed.Client`` of the scheduler at ``address``, or one clear error.

    Parameters
    ----------
    address : str
        The scheduler's address, e.g. ``"tcp://127.0.0.1:8786"``.
    timeout : float
        Seconds to wait for the scheduler.

    Returns
    -------
    distributed.Client
        Connected; the default scheduler of later ``.compute()`` calls until it is closed.

    Raises
    ------
    GridfieldError
        If the scheduler cannot be reached within ``timeout`` seconds, or Dask is not installed.

    Examples
    --------
    >>> connect("tcp://127.0.0.1:1", timeout=0.5)
    Traceback (most recent call last):
    ...
    gridfield.core.errors.GridfieldError: cannot connect to the Dask scheduler 'tcp://127.0.0.1:1' within 0.5 s: ...
    """
    if not isinstance(address, str) or not address:
        raise ParameterError(f"address must be a scheduler address such as 'tcp://host:8786', got {shorten(address)}")
    try:
        from distributed import Client
    except ImportError:
        raise GridfieldError("connecting to a Dask scheduler needs Dask: pip install 'gridfield[dask]'") from None
    # A Client that fails to connect has already made itself the default (and set dask's scheduler to it),
    # and nothing public undoes that: a later compute() would wait on the dead address. So the address is
    # probed by a client that is never the default, and only a reachable one gets the default client.
    try:
        Client(address, timeout=timeout, set_as_default=False).close()
    except (OSError, ValueError, TypeError) as e:  # TimeoutError is an OSError
        message = " ".join((str(e) or type(e).__name__).split())[:200]
        raise GridfieldError(f"cannot connect to the Dask scheduler {address!r} within {timeout:g} s: {message}") from None
    return Client(address, timeout=timeout)
