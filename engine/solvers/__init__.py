"""Contact, wear and subsurface-stress solvers (no MPI, no files)."""
