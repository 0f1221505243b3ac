"""linkcli: a command-line design tool for planar linkages."""

__version__ = "0.1.0"
