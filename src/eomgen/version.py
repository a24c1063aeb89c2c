"""The package version (generated files name it)."""
__version__ = "0.1.0"
