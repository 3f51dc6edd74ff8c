"""Output layer: what a running study writes (HDF5 results file, summary table, lock,
progress). Post-processing (reader, report, figures) is the analysis layer, engine.analysis."""
