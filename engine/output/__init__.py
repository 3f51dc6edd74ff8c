"""Output layer: HDF5 results file and the pandas summary."""
