"""The ``baobab`` command line: one module per subcommand, and the process's start-up."""
