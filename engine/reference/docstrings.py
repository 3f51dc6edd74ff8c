"""The numpydoc sections of the analytic solutions, assembled from entries written once.

Several closed-form functions take the same parameters (load, radius, contact modulus …).
Each module writes those entries once as ``"name : type\\n    description"`` texts and
completes its functions' docstrings with :func:`documented`; the rendered docstrings (``help``,
the API reference) list every parameter in full.
"""

from __future__ import annotations

import inspect

__all__ = ["documented"]


def documented(returns: str, *parameters: str):
    """Decorator: complete a docstring with its Parameters and Returns sections.

    Parameters
    ----------
    returns : str
        The Returns entry, ``"type\\n    description"``.
    *parameters : str
        The Parameters entries in the order of the signature, each
        ``"name : type\\n    description"``.

    Returns
    -------
    callable
        A decorator that appends the two sections to the function's own docstring (its summary
        and physics) and returns the function.
    """

    def complete(function):
        text = (
            f"{inspect.cleandoc(function.__doc__)}\n\n"
            f"Parameters\n----------\n" + "\n".join(parameters) + "\n\n"
            f"Returns\n-------\n{returns}"
        )
        function.__doc__ = text.replace("\n", "\n    ")
        return function

    return complete
