"""One process alone, without MPI: the communicator of a run that no MPI launcher started.

``python -m engine STUDY.toml`` typed without ``mpiexec`` or ``srun`` runs on one process; it
need not initialise MPI nor load mpi4py (about 17 MB of the process's memory and a tenth of a
second of its start). :class:`SerialComm` answers the calls the study, parallel and output
layers make of a communicator of size one, exactly as ``MPI.COMM_SELF`` would: every
collective returns this rank's own contribution. Point-to-point calls do not exist (there is
no peer); the layers make none with one rank.

:func:`any_rank` and :func:`ranks_on_node` are the collectives both kinds of communicator
answer without MPI's constants. Where a library needs an mpi4py communicator (h5py's
``mpio`` driver, ``engine.output.collective``), a ``SerialComm`` stands for
``MPI.COMM_SELF``.
"""

from __future__ import annotations

import os
import sys
from typing import Any

__all__ = ["SerialComm", "any_rank", "ranks_on_node"]


class SerialComm:
    """A communicator of one rank (rank 0, size 1) that never loads MPI."""

    def Get_rank(self) -> int:  # noqa: N802 - mpi4py's names
        return 0

    def Get_size(self) -> int:  # noqa: N802
        return 1

    def bcast(self, value: Any, root: int = 0) -> Any:
        return value

    def gather(self, value: Any, root: int = 0) -> list[Any]:
        return [value]

    def allgather(self, value: Any) -> list[Any]:
        return [value]

    def allreduce(self, value: Any, op: Any = None) -> Any:
        return value

    def Barrier(self) -> None:  # noqa: N802
        return None

    def Abort(self, errorcode: int = 1) -> None:  # noqa: N802
        """End the process at once with ``errorcode``, as ``MPI_Abort`` does."""
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(errorcode)


def any_rank(comm, flag: bool) -> bool:
    """Collective: whether ``flag`` is true on any rank of ``comm`` (logical-or reduction)."""
    if comm.Get_size() == 1:
        return bool(flag)
    from mpi4py import MPI

    return bool(comm.allreduce(bool(flag), op=MPI.LOR))


def ranks_on_node(comm) -> int:
    """Collective: the ranks of ``comm`` on this rank's node (shared-memory split)."""
    if comm.Get_size() == 1:
        return 1
    from mpi4py import MPI

    return comm.Split_type(MPI.COMM_TYPE_SHARED).Get_size()
