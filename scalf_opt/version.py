"""The version of scalf-opt: one place, read by the package, the provenance records and the CLI."""

__version__ = "0.1.0"
