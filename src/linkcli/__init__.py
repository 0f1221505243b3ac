"""linkcli: a command-line design tool for planar four-bar linkages."""

__version__ = "0.1.0"
