"""The package version (one place: ``pyproject.toml`` reads it, results files store it)."""

__version__ = "0.1.0"
