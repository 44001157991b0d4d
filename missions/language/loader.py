"""Load a mission file into a validated :class:`Mission`, or fail with one located error.

Order of work (each step's errors come before the next step's):

1. the located YAML loader (syntax, duplicate keys, aliases, nesting, size, NaN), unknown
   top-level keys (a ``# yaml-language-server: $schema=...`` comment is optional, for editors);
2. ``params`` and the ``--set`` overrides; ``${name}`` substitution into start, tree, events,
   noise, collision_monitor, timeout and expect (and a refusal of ``${`` anywhere else);
3. the top-level model (types, events, expectations);
4. robot (a bundled name or a robot file inside the mission's folder, or the ``--robot``
   override; one of ``robots:`` when the mission lists the robots it fits), world (a bundled
   name or a file inside the mission's folder: a world file or a map_server map YAML; or
   ``--world``), the mission's own route graph (a GeoJSON file inside the folder, checked
   against the world), the mission's costmap filter masks, and locations (the world's spawns and
   locations, then the mission's, which win);
5. start pose, the collision monitor (the world's and the mission's blocks), the tree (node
   types, capabilities, parameters, goal poses in free space), every subtree body, then the
   cross-checks of events and expectations.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

from pydantic import TypeAdapter, ValidationError

from baobab.behaviours.builtin import default_registry
from baobab.behaviours.poses import MissionScope, Pose
from baobab.behaviours.registry import Registry
from baobab.missions.language.collision_monitor_block import (
    check_toggles,
    mission_collision_monitor,
)
from baobab.missions.language.cross_checks import MissionChecks
from baobab.missions.language.errors import MissionError, describe_validation_error, located
from baobab.missions.language.mission import Mission
from baobab.missions.language.models import (
    SUBSTITUTED_SECTIONS,
    TOP_LEVEL_KEYS,
    MissionFile,
    ParamName,
)
from baobab.missions.language.params import (
    ParamSpec,
    Substitution,
    check_no_placeholders,
    resolve_values,
)
from baobab.missions.language.tree_parser import TreeParser
from baobab.robots.catalog import RobotInfo, robot_named
from baobab.robots.robot_file import is_robot_path, load_robot, load_robot_file
from baobab.sim.errors import BaobabError, unknown_name
from baobab.sim.input_files import file_kind_problem
from baobab.sim.route_graph_file import load_route_graph
from baobab.sim.route_graph_geometry import check_on_world
from baobab.sim.world import Pose2D, World, bundled_world_names, load_world
from baobab.sim.world_map import FilterSettings
from baobab.sim.yaml_source import (
    FieldValueError,
    KeyPath,
    LocatedDocument,
    load_located_yaml,
    read_yaml_text,
)

if TYPE_CHECKING:
    from baobab.nav.nav2_params_file import Nav2ParamsFile

PLACEHOLDER_FREE = (
    "mission",
    "world",
    "robot",
    "robots",
    "nav2_params",
    "seed",
    "params",
    "locations",
    "filters",
)
"""Top-level keys where ``${...}`` is refused (parameters cannot choose them)."""

SCHEMA_HEADER = "# yaml-language-server: $schema="
"""The editor comment that bundled and generated missions begin with, before the schema's
location; optional in a mission file."""
_PARAMS = TypeAdapter(dict[ParamName, ParamSpec])


def load_mission(
    path: str | Path,
    overrides: Mapping[str, str] | None = None,
    *,
    text: str | None = None,
    registry: Registry | None = None,
    robot: str | None = None,
    world: str | Path | None = None,
    nav2_params: str | Path | None = None,
    nav2_substitute: bool = False,
) -> Mission:
    """Load, substitute and validate a mission file.

    Args:
        path: the mission file (also names it in messages when ``text`` is given).
        overrides: ``--set`` values by parameter name, as written on the command line.
        text: the file's content, if already in memory.
        registry: node types; default: :func:`default_registry`.
        robot: ``--robot``: a bundled robot's name or a robot file's path (from the working
            directory) that replaces the mission's ``robot:``, if the mission fits it.
        world: a world in place of the mission's (``--world``): a bundled name, a world file
            or a map_server map YAML anywhere (the user named it); a mobile robot's only.
        nav2_params: ``--nav2-params``: a Nav2 parameter file (anywhere: the user named it)
            in place of the mission's ``nav2_params:``.
        nav2_substitute: ``--nav2-substitute``: accept the stated substitutes of the plugins
            baobab does not have.

    Raises:
        MissionError: the first problem, as ``path:line:col: message``.
        WorldError: a problem inside the world file the mission names.
        RobotFileError: a problem inside the robot file the mission or ``robot`` names.
        BaobabError: ``robot`` names no bundled robot.
        Nav2ParamsError: a problem inside the Nav2 parameter file (located there).
    """
    mission_path = Path(path)
    if text is None:
        text = read_yaml_text(mission_path, MissionError)
    document = load_located_yaml(mission_path, MissionError, text=text)
    loader = _Loader(mission_path, document, text, registry or default_registry(), world)
    loader.nav2_override = nav2_params
    mission = loader.load(overrides or {}, robot)
    return _with_nav2_params(mission, nav2_params is not None, nav2_substitute)


class _Loader:
    def __init__(
        self,
        path: Path,
        document: LocatedDocument,
        text: str,
        registry: Registry,
        world: str | Path | None = None,
    ) -> None:
        self.path = path
        self.document = document
        self.text = text
        self.registry = registry
        self.world_override = world
        self.nav2_override: str | Path | None = None
        self.origins: dict[KeyPath, str] = {}

    def _error(self, path: KeyPath, message: str) -> MissionError:
        return located(self.document, path, message, self.origins)

    def load(self, overrides: Mapping[str, str], robot_override: str | None) -> Mission:
        data = self._top_level()
        specs = self._params(data.get("params", {}))
        values = resolve_values(specs, overrides, self.document)
        file = self._validated(data, values, {k: spec.type for k, spec in specs.items()})
        robot = self._robot(file, robot_override)
        world, world_name = self._world(file.world, robot)
        world = self._route_graph(file.route_graph, world)
        if file.filters is not None:
            world = self._filters(file.filters, world)
        nav2_params = self._nav2_params(file)
        scope = MissionScope(
            robot, world, self._locations(file, robot, world), self.path.parent.resolve()
        )
        start = self._start(file.start, scope, world)
        monitor = mission_collision_monitor(
            self.document,
            file.collision_monitor,
            robot,
            (world, world_name),
            nav2_params,
            self.origins,
        )
        parser = TreeParser(self.document, self.registry, scope, file.subtrees, self.origins)
        tree = parser.parse(file.tree, ("tree",))
        check_toggles(self.document, tree, monitor is not None)
        shapes = {name: parser.check_template(name, spec) for name, spec in file.subtrees.items()}
        checks = MissionChecks(self.document, scope, self.origins)
        checks.events(file.events, file.timeout)
        checks.noise(file.noise)
        if file.expect is not None:
            checks.expect(file.expect, file.timeout)
        return Mission(
            path=self.path,
            name=file.mission,
            description=file.description,
            robot=robot,
            supported_robots=None if file.robots is None else tuple(file.robots),
            world=world,
            world_name=world_name,
            start=start,
            seed=file.seed,
            params=values,
            locations=dict(scope.locations),
            tree=tree,
            subtrees=dict(file.subtrees),
            subtree_shapes=shapes,
            events=tuple(sorted(file.events, key=lambda event: event.at)),
            timeout=file.timeout,
            expect=file.expect,
            document=self.document,
            noise=file.noise,
            nav2_params=nav2_params,
            collision_monitor=monitor,
        )

    def _validated(
        self, data: dict[str, Any], values: Mapping[str, Any], types: Mapping[str, Any]
    ) -> MissionFile:
        """The top level with the parameters substituted, checked against the model."""
        for key in PLACEHOLDER_FREE:
            if key in data:
                check_no_placeholders(self.document, data[key], (key,))
        substitution = Substitution(self.document, values, types, "the mission")
        substituted = {
            key: substitution.apply(value, (key,)) if key in SUBSTITUTED_SECTIONS else value
            for key, value in data.items()
        }
        self.origins.update(substitution.origins)
        try:
            return MissionFile.model_validate(substituted)
        except ValidationError as exc:
            raise describe_validation_error(
                self.document,
                exc,
                data=substituted,
                base_path=(),
                label="",
                model=MissionFile,
                origins=self.origins,
                nouns={("expect",): "expectation", ("params",): "parameter"},
            ) from None

    def _nav2_params(self, file: MissionFile) -> Nav2ParamsFile | None:
        """The Nav2 parameter file (``--nav2-params`` over ``nav2_params:``), or None."""
        if self.nav2_override is not None:
            return _read_nav2(Path(self.nav2_override))
        if file.nav2_params is not None:
            return _read_nav2(self._file_in_folder("nav2_params", file.nav2_params))
        return None

    def _top_level(self) -> dict[str, Any]:
        data = self.document.data
        if not isinstance(data, dict):
            raise self._error((), "a mission file is a mapping of top-level keys")
        for key in data:
            if key not in TOP_LEVEL_KEYS:
                raise self._error((key,), unknown_name("top-level key", key, TOP_LEVEL_KEYS))
        return data

    def _params(self, raw: Any) -> dict[str, ParamSpec]:
        try:
            return _PARAMS.validate_python(raw)
        except ValidationError as exc:
            raise describe_validation_error(
                self.document,
                exc,
                data=raw,
                base_path=("params",),
                label="params",
                model=dict[ParamName, ParamSpec],
            ) from None

    def _world(self, written: str | None, robot: RobotInfo) -> tuple[World | None, str]:
        if self.world_override is not None:
            if not robot.mobile:
                raise BaobabError(
                    f"--world: robot '{robot.name}' stands in its own scene "
                    f"({', '.join(robot.scenes)}); --world is for mobile robots"
                )
            return load_world(self.world_override), str(self.world_override)
        if not robot.mobile:
            if written is None:
                return None, robot.scenes[0]
            if written not in robot.scenes:
                message = unknown_name(f"scene for robot '{robot.name}'", written, robot.scenes)
                raise self._error(("world",), message)
            return None, written
        bundled = bundled_world_names()
        if written is None:
            raise self._error(
                ("robot",),
                f"robot '{robot.name}' needs a world: a bundled name "
                f"({', '.join(bundled) or 'none installed'}) or a world file in the mission's "
                "folder",
            )
        if "/" not in written and "\\" not in written and not written.endswith((".yaml", ".yml")):
            if written not in bundled:
                raise self._error(("world",), unknown_name("world", written, bundled))
            return load_world(written), written
        resolved = self._file_in_folder("world", written)
        return load_world(resolved), str(resolved)

    def _file_in_folder(self, key: str, written: str) -> Path:
        """The file ``written`` under ``key`` names, checked to lie inside the mission's folder."""
        relative = Path(written)
        folder = self.path.resolve().parent  # the real folder of a linked mission file
        resolved = (folder / relative).resolve()
        if relative.is_absolute() or not resolved.is_relative_to(folder):
            raise self._error(
                (key,),
                f"{key} file '{written}' is outside the mission's folder; give "
                + ("a" if key == "route_graph" else f"a bundled {key} name or a")
                + " path inside the folder",
            )
        try:
            problem = file_kind_problem(resolved.stat().st_mode)
        except OSError:
            problem = "does not exist"
        if problem == "does not exist":
            raise self._error((key,), f"no {key} file '{written}' in the mission's folder")
        if problem is not None:
            raise self._error((key,), f"{key} file '{written}' {problem}; expected a file")
        return resolved

    def _robot(self, file: MissionFile, override: str | None) -> RobotInfo:
        """The mission's robot, or ``--robot``'s, checked against the robots it fits."""
        if override is not None:
            robot = load_robot(override)
        elif is_robot_path(file.robot):
            robot = load_robot_file(self._file_in_folder("robot", file.robot))
        else:
            found = robot_named(file.robot)
            if found is None:  # pragma: no cover - the model checked the name
                raise self._error(("robot",), f"unknown robot '{file.robot}'")
            robot = found
        supported = file.robots
        if supported is not None and robot.name not in supported:
            where = ("robots",) if override is not None else ("robot",)
            given = f"--robot {override}" if override is not None else f"robot '{robot.name}'"
            kind = "robot file" if robot.path else "robot"
            raise self._error(
                where,
                f"{given}: this mission fits only {', '.join(supported)} (robots:), not the "
                f"{kind} '{robot.name}'",
            )
        return robot

    def _route_graph(self, written: str | None, world: World | None) -> World | None:
        """The world with the mission's own route graph in place of its own, if it names one.

        Raises:
            MissionError: no mobile robot's world, or the file outside the folder or missing.
            WorldError: a mistake in the graph file, or a node or edge the world makes
                impossible (located in the graph file).
        """
        if written is None:
            return world
        if world is None:
            raise self._error(("route_graph",), "a route graph needs a mobile robot's world")
        resolved = self._file_in_folder("route_graph", written)
        graph = load_route_graph(resolved)
        check_on_world(graph, world)
        return world.with_route_graph(graph)

    def _filters(self, filters: FilterSettings, world: World | None) -> World:
        """The world with the mission's costmap filter masks (files in the mission's folder)."""
        if world is None:
            raise self._error(("filters",), "filters apply to a mobile robot's world")
        try:
            return world.with_filters(filters, self.path.resolve().parent)
        except FieldValueError as exc:
            raise self._error(("filters", *exc.key_path), str(exc)) from None

    def _locations(
        self, file: MissionFile, robot: RobotInfo, world: World | None
    ) -> dict[str, Pose]:
        locations: dict[str, Pose] = {}
        if world is not None:
            for name, planar in {**world.spawns, **world.locations}.items():
                locations[name] = Pose.from_planar(planar.x, planar.y, planar.yaw).named(name)
        for name, pose in file.locations.items():
            if world is not None and robot.mobile and not world.contains(pose.x, pose.y):
                raise self._error(
                    ("locations", name),
                    f"location '{name}' ({pose.x:.2f}, {pose.y:.2f}) is outside the floor of "
                    f"world '{world.name}'",
                )
            locations[name] = pose.named(name)
        return locations

    def _start(self, written: Any, scope: MissionScope, world: World | None) -> Pose2D | None:
        robot = scope.robot
        if not robot.mobile:
            if written is not None:
                raise self._error(
                    ("start",), f"start applies to mobile robots; {robot.name} stands still"
                )
            return None
        if written is None:
            if world is None:
                return None
            if "default" not in world.spawns:
                raise self._error(
                    ("world",),
                    f"world '{world.name}' is a map with no spawn; give the mission a start: "
                    "a pose [x, y, yaw] or a location, in free space",
                )
            spawn = Pose.from_planar(world.spawn.x, world.spawn.y, world.spawn.yaw)
            problem = scope.free_space_problem(spawn)
            if problem is not None:
                raise self._error(
                    ("world",),
                    f"the start (world '{world.name}', spawn 'default') {problem}; give the "
                    "mission a start: in free space",
                )
            return world.spawn
        try:
            pose = scope.resolve(written)
        except ValidationError as exc:
            raise describe_validation_error(
                self.document, exc, data=written, base_path=("start",), label="start"
            ) from None
        except ValueError as exc:
            raise self._error(("start",), f"start: {exc}") from None
        problem = scope.free_space_problem(pose)
        if problem is not None:
            raise self._error(("start",), f"start {problem}")
        return pose.pose2d()


def _read_nav2(path: Path) -> Nav2ParamsFile:
    """The mission's Nav2 parameter file, read (its own errors are located in it)."""
    from baobab.nav.nav2_params_file import read_nav2_params

    return read_nav2_params(path)


def _with_nav2_params(mission: Mission, overridden: bool, substitute: bool) -> Mission:
    """``mission`` with its Nav2 parameter file (``--nav2-params`` when ``overridden``) checked
    against the navigation stack (types, ranges, plugins), its filter masks laid on the world
    and its warning made."""
    params = mission.nav2_params
    if params is None:
        return mission
    if not mission.robot.mobile:
        message = f"robot '{mission.robot.name}' has no navigation stack for a Nav2 parameter file"
        if overridden:
            raise BaobabError(f"--nav2-params: {message}")
        raise located(mission.document, ("nav2_params",), message)
    from baobab.nav.nav2_configuration import configure_navigation

    configuration = configure_navigation(params, substitute=substitute)
    world = mission.world if mission.world is None else configuration.filtered(mission.world)
    return replace(
        mission,
        world=world,
        nav2_params=params,
        nav2_substitute=substitute,
        nav2_warning=configuration.warning(),
    )
