"""Command line interface: ``ringcore SUBCOMMAND ...`` (see ``ringcore --help``)."""
