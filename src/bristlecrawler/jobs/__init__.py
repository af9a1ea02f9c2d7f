"""Jobs: complete runs that read a configuration and write a run folder (used by the CLI)."""
