"""Parallel layer: who runs which case (receives a communicator, never COMM_WORLD)."""
