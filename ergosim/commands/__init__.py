"""CLI subcommands, one module each (see ergosim.cli)."""
