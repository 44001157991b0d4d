"""The ``baobab`` command line: the parser, its subcommands, and how a command's errors end it.

Each subcommand is one module here (``<name>_command.py``) with a ``configure_<name>`` that declares
its arguments and a handler that runs it; :data:`SUBCOMMANDS` lists them. Exit codes
(:mod:`baobab.missions.run.exit_codes`): 0 as intended, 1 ran but not as intended, 2 invalid input
(located messages on stderr, never a traceback), 3 ran but could not be saved (``run``), 128 +
signal when SIGINT (130), SIGTERM (143) or SIGHUP (129) ended it
(:mod:`baobab.missions.cli.interrupts`).

Start-up time is a product figure (``baobab validate`` of every bundled mission in well under
half a second): a subcommand's module is imported when that subcommand is asked for (building
the parser for ``baobab run`` imports only ``run_command``), and what only one command needs
(py_trees for a compiled tree, json, the behaviour catalogue) inside that command's handler.
"""

from __future__ import annotations

from baobab.missions.cli.startup import environment_defaults, skip_pydantic_plugin_discovery

environment_defaults()  # before MuJoCo or pydantic load

import argparse  # noqa: E402
import sys  # noqa: E402
from collections.abc import Callable, Sequence  # noqa: E402
from dataclasses import dataclass  # noqa: E402
from typing import TYPE_CHECKING, NoReturn  # noqa: E402

from baobab.missions.cli.interrupts import signals_for  # noqa: E402
from baobab.missions.run.exit_codes import EXIT_INTERRUPTED, EXIT_INVALID  # noqa: E402
from baobab.sim.errors import BaobabError, SourceError, one_line  # noqa: E402

if TYPE_CHECKING:
    from baobab.missions.run.child_process import StartedChild

Handler = Callable[[argparse.Namespace], int]
"""Runs a subcommand on its parsed arguments; returns the exit code."""


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``baobab`` console script; returns the exit code."""
    skip_pydantic_plugin_discovery()
    arguments = list(sys.argv[1:] if argv is None else argv)
    for argument in arguments:
        if not _is_utf8(argument):
            # A run writes its arguments (--set values, paths) into UTF-8 files (result.json,
            # the trace): refuse them now rather than after the simulation.
            print(
                f"baobab: argument '{one_line(argument)}' is not valid UTF-8 text; "
                "write it (and name files) in UTF-8",
                file=sys.stderr,
            )
            return EXIT_INVALID
    command = next((argument for argument in arguments if not argument.startswith("-")), None)
    run_process = None
    if command == "run":  # its process loads the simulation stack while this one starts up
        from baobab.missions.cli.run_process import start_run_process

        run_process = start_run_process()
    try:
        return _parse_and_handle(arguments, command, run_process)
    finally:
        if run_process is not None:
            run_process.discard()  # unused (refused input, --help) or done: ended, reaped


def _parse_and_handle(
    arguments: list[str], command: str | None, run_process: StartedChild | None
) -> int:
    """Parse ``arguments`` and run the command they name; returns the exit code."""
    parser = build_parser(command)
    extras: dict[str, list[str]] = {}
    if command == "ros":  # `-- --ros-args ...` and `name:=value` words are not argparse's
        from baobab.missions.cli.ros_command import split_arguments

        arguments, extras = split_arguments(arguments)
    try:
        args = parser.parse_args(arguments)
    except SystemExit as exit_:  # argparse: --help (0) or a usage error (2)
        return int(exit_.code or 0)
    vars(args).update(extras)
    if run_process is not None:
        args.run_process = run_process
    handler: Handler = args.handler
    signals_for(args.command)
    try:
        return handler(args)
    except SourceError as exc:
        print(exc, file=sys.stderr)
        return EXIT_INVALID
    except BaobabError as exc:
        print(one_line(f"baobab {args.command}: {exc}"), file=sys.stderr)
        return EXIT_INVALID
    except KeyboardInterrupt:
        return EXIT_INTERRUPTED


def _is_utf8(argument: str) -> bool:
    """False for an argument with bytes that are not UTF-8 (``os.fsdecode`` keeps them as
    lone surrogates)."""
    try:
        argument.encode("utf-8")
    except UnicodeEncodeError:
        return False
    return True


class _Parser(argparse.ArgumentParser):
    """argparse with its usage errors on one line (exit 2); ``--help`` is unchanged."""

    def error(self, message: str) -> NoReturn:
        """Print ``baobab run: <what is wrong> (see baobab run --help)`` and exit 2."""
        self.exit(EXIT_INVALID, f"{one_line(f'{self.prog}: {message}')} (see {self.prog} --help)\n")


def build_parser(command: str | None = None) -> argparse.ArgumentParser:
    """The argument parser with every subcommand.

    Args:
        command: when it names a subcommand, only that one's arguments are set up (setting up
            the others imports what only they need, e.g. the teleop terminal for ``teleop``).
    """
    parser = _Parser(
        prog="baobab",
        description="Robot missions in YAML, compiled to behaviour trees, run over MuJoCo.",
    )
    commands = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for name, subcommand in SUBCOMMANDS.items():
        sub = commands.add_parser(name, help=subcommand.summary, description=subcommand.summary)
        if command not in SUBCOMMANDS or name == command:
            subcommand.configure(sub)
        sub.set_defaults(handler=subcommand.handler)
    return parser


@dataclass(frozen=True)
class Subcommand:
    """One ``baobab`` subcommand.

    Attributes:
        configure: declares its arguments on its parser.
        handler: runs it.
        summary: its one-line help.
    """

    configure: Callable[[argparse.ArgumentParser], None]
    handler: Handler
    summary: str


# Each subcommand's module is imported by these when that subcommand is used (start-up).


def _configure_run(parser: argparse.ArgumentParser) -> None:
    from baobab.missions.cli.run_command import configure_run

    configure_run(parser)


def _run(args: argparse.Namespace) -> int:
    from baobab.missions.cli.arguments import overrides
    from baobab.missions.cli.run_command import run_command

    return run_command(args, overrides(args))


def _configure_validate(parser: argparse.ArgumentParser) -> None:
    from baobab.missions.cli.validate_command import configure_validate

    configure_validate(parser)


def _validate(args: argparse.Namespace) -> int:
    from baobab.missions.cli.validate_command import validate_command

    return validate_command(args)


def _configure_tree(parser: argparse.ArgumentParser) -> None:
    from baobab.missions.cli.tree_command import configure_tree

    configure_tree(parser)


def _tree(args: argparse.Namespace) -> int:
    from baobab.missions.cli.tree_command import tree_command

    return tree_command(args)


def _configure_schema(parser: argparse.ArgumentParser) -> None:
    from baobab.missions.cli.schema_command import configure_schema

    configure_schema(parser)


def _schema(args: argparse.Namespace) -> int:
    from baobab.missions.cli.schema_command import schema_command

    return schema_command(args)


def _configure_list(parser: argparse.ArgumentParser) -> None:
    from baobab.missions.cli.list_command import configure_list

    configure_list(parser)


def _list(args: argparse.Namespace) -> int:
    from baobab.missions.cli.list_command import list_command

    return list_command(args)


def _configure_teleop(parser: argparse.ArgumentParser) -> None:
    from baobab.missions.cli.teleop_command import configure_teleop

    configure_teleop(parser)


def _teleop(args: argparse.Namespace) -> int:
    from baobab.missions.cli.teleop_command import teleop_command

    return teleop_command(args)


def _configure_campaign(parser: argparse.ArgumentParser) -> None:
    from baobab.missions.cli.campaign_command import configure_campaign

    configure_campaign(parser)


def _campaign(args: argparse.Namespace) -> int:
    from baobab.missions.cli.arguments import overrides
    from baobab.missions.cli.campaign_command import campaign_command

    return campaign_command(args, overrides(args))


def _configure_nav2(parser: argparse.ArgumentParser) -> None:
    from baobab.missions.cli.nav2_command import configure_nav2

    configure_nav2(parser)


def _nav2(args: argparse.Namespace) -> int:
    from baobab.missions.cli.nav2_command import nav2_command

    return nav2_command(args)


def _configure_nav2_params(parser: argparse.ArgumentParser) -> None:
    from baobab.missions.cli.nav2_params_command import configure_nav2_params

    configure_nav2_params(parser)


def _nav2_params(args: argparse.Namespace) -> int:
    from baobab.missions.cli.nav2_params_command import nav2_params_command

    return nav2_params_command(args)


def _configure_ros(parser: argparse.ArgumentParser) -> None:
    from baobab.missions.cli.ros_command import configure_ros

    configure_ros(parser)


def _ros(args: argparse.Namespace) -> int:
    from baobab.missions.cli.ros_command import ros_command

    return ros_command(args)


SUBCOMMANDS: dict[str, Subcommand] = {
    "run": Subcommand(_configure_run, _run, "run a mission and write its run folder"),
    "validate": Subcommand(
        _configure_validate, _validate, "check mission files without running them"
    ),
    "tree": Subcommand(_configure_tree, _tree, "print a mission's compiled behaviour tree"),
    "schema": Subcommand(_configure_schema, _schema, "print the JSON Schema of the mission format"),
    "list": Subcommand(
        _configure_list, _list, "list bundled missions, worlds, robots and behaviours"
    ),
    "teleop": Subcommand(_configure_teleop, _teleop, "drive with the keyboard, assisted teleop on"),
    "campaign": Subcommand(
        _configure_campaign, _campaign, "seeded sweeps of a mission, in parallel"
    ),
    "nav2": Subcommand(_configure_nav2, _nav2, "run a Nav2 Simple Commander script"),
    "nav2-params": Subcommand(
        _configure_nav2_params,
        _nav2_params,
        "show how a Nav2 parameter file configures baobab's navigation stack",
    ),
    "ros": Subcommand(_configure_ros, _ros, "run rclpy node files or a launch file on sim time"),
}
"""Subcommand name -> its arguments, handler and help, in the order ``baobab --help`` lists them."""
