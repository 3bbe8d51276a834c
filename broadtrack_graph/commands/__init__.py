"""Subcommands of the command line, one module each (see broadtrack_graph.cli)."""
