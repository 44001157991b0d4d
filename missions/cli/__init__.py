"""The ``baobab`` command line (console script :func:`.entry.main`).

:mod:`.command_line` builds the parser from :data:`~.command_line.SUBCOMMANDS`; each
subcommand is one module, ``<name>_command.py`` (``run``, ``validate``, ``tree``, ``schema``,
``list``, ``teleop``, ``campaign``, ``nav2``, ``ros``), with ``configure_<name>`` for its
arguments and its handler; :mod:`.arguments` holds the argument types they share. The process
around them: :mod:`.entry` (signals first), :mod:`.startup`, :mod:`.interrupts`,
:mod:`.streams`.

This package imports nothing itself (see :mod:`.entry`).
"""
