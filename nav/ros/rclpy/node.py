"""``rclpy.node``: a node with publishers, subscriptions, timers, rates, parameters, a logger and
a simulation-time clock.

Topics live in the in-process graph (:mod:`baobab.nav.ros.graph`): under ``baobab ros run``
the run's graph, shared with the simulation's topics; in a Nav2 script, the graph of the
script's own context. Names resolve as in ROS (relative names under the node's namespace,
``~`` for the node's own, ``--ros-args -r`` remaps). The clock is a ROS-time clock reading
the simulation time, as nodes with ``use_sim_time`` do (the parameter is declared true).
Services and actions are not modelled: asking for one raises
:class:`~baobab.nav.ros.UnsupportedRosFeatureError`. ``BasicNavigator`` is a node too.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Sequence
from typing import Any, NoReturn

from baobab.nav.ros import UnsupportedRosFeatureError, waiting
from baobab.nav.ros.arguments import (
    RosArguments,
    expand_topic_name,
    node_identity,
    parse_ros_arguments,
    remap_topic,
)
from baobab.nav.ros.qos import QoSProfile, as_profile
from baobab.nav.ros.rcl_interfaces.msg import ParameterDescriptor, SetParametersResult
from baobab.nav.ros.rclpy._parameters import ParameterStore, SetCallback
from baobab.nav.ros.rclpy.context import Context, get_default_context
from baobab.nav.ros.rclpy.exceptions import InvalidTopicNameException
from baobab.nav.ros.rclpy.logging import LoggingSeverity, RcutilsLogger
from baobab.nav.ros.rclpy.parameter import Parameter
from baobab.nav.ros.rclpy.publisher import Publisher
from baobab.nav.ros.rclpy.subscription import Subscription
from baobab.nav.ros.rclpy.timer import Rate, Timer
from baobab.nav.rostime import S_TO_NS, Clock, ClockType

__all__ = ["Node"]


class Node:
    """A ROS node (``rclpy.node.Node``); see the module docstring.

    Args:
        node_name: the node's name, also its logger's (``-r __node:=`` renames it).
        context: the lifecycle the node belongs to; the default context when ``None``.
        cli_args: the node's own ``--ros-args``, on top of the context's.
        namespace: the node's namespace (``"/"`` when ``None`` or empty).
        use_global_arguments: also apply the context's ``--ros-args``.
        parameter_overrides: ``Parameter`` values that win over every other source.
        allow_undeclared_parameters: get and set parameters never declared.
        automatically_declare_parameters_from_overrides: declare every override.
        **options: rclpy's other options (rosout, parameter services, ...): accepted.
    """

    def __init__(
        self,
        node_name: str,
        *,
        context: Context | None = None,
        cli_args: Sequence[str] | None = None,
        namespace: str | None = None,
        use_global_arguments: bool = True,
        parameter_overrides: Sequence[Parameter] | None = None,
        allow_undeclared_parameters: bool = False,
        automatically_declare_parameters_from_overrides: bool = False,
        **options: object,
    ) -> None:
        self._context = get_default_context() if context is None else context
        arguments = self._context.arguments if use_global_arguments else RosArguments()
        if cli_args:
            arguments = arguments.merged(parse_ros_arguments(list(cli_args)))
        self._arguments = arguments
        self._name, self._namespace = node_identity(node_name, namespace, arguments.remaps)
        self._graph = self._context.graph
        self._logger = RcutilsLogger(self._name)
        level = arguments.log_levels.get(self._name, arguments.log_levels.get(""))
        if level is not None and level in LoggingSeverity.__members__:
            self._logger.set_level(LoggingSeverity[level])
        self._clock = Clock(clock_type=ClockType.ROS_TIME)
        overrides = arguments.overrides_for(self._name, self._namespace)
        for parameter in parameter_overrides or ():
            overrides[parameter.name] = parameter.value
        self._parameters = ParameterStore(
            self._name,
            overrides,
            allow_undeclared=allow_undeclared_parameters,
            declare_overrides=automatically_declare_parameters_from_overrides,
        )
        if not self._parameters.has("use_sim_time"):
            self._parameters.declare("use_sim_time", True)
        self._publishers: list[Publisher] = []
        self._subscriptions: list[Subscription] = []
        self._timers: list[Timer] = []
        self.executor: Any = None
        self._destroyed = False
        self._context.track_node(self)

    # -- identity -----------------------------------------------------------------------------

    @property
    def context(self) -> Context:
        """The lifecycle this node belongs to."""
        return self._context

    def get_name(self) -> str:
        """The node's name."""
        return self._name

    def get_namespace(self) -> str:
        """The node's namespace, ``"/"`` at the root."""
        return self._namespace

    def get_fully_qualified_name(self) -> str:
        """Namespace and name, such as ``/basic_navigator``."""
        return f"{self._namespace.rstrip('/')}/{self._name}"

    def get_logger(self) -> RcutilsLogger:
        """The node's logger."""
        return self._logger

    def get_clock(self) -> Clock:
        """The node's ROS-time clock (simulation time)."""
        return self._clock

    @property
    def publishers(self) -> Iterator[Publisher]:
        """The node's publishers."""
        return iter(list(self._publishers))

    @property
    def subscriptions(self) -> Iterator[Subscription]:
        """The node's subscriptions."""
        return iter(list(self._subscriptions))

    @property
    def timers(self) -> Iterator[Timer]:
        """The node's timers."""
        return iter(list(self._timers))

    def resolve_topic_name(self, topic: str, *, only_expand: bool = False) -> str:
        """The fully qualified name of ``topic`` for this node, after remapping.

        Raises:
            InvalidTopicNameException: ``topic`` breaks ROS's naming rules.
        """
        try:
            expanded = expand_topic_name(topic, self._name, self._namespace)
        except ValueError as exc:
            raise InvalidTopicNameException(topic, str(exc)) from None
        if only_expand:
            return expanded
        return remap_topic(expanded, self._arguments.remaps, self._name, self._namespace)

    # -- topics -------------------------------------------------------------------------------

    def create_publisher(
        self, msg_type: type, topic: str, qos_profile: QoSProfile | int, **options: object
    ) -> Publisher:
        """A publisher of ``msg_type`` on ``topic``; an int ``qos_profile`` is a KEEP_LAST depth."""
        self._check_type(msg_type)
        publisher = Publisher(
            self._graph, msg_type, self.resolve_topic_name(topic), as_profile(qos_profile)
        )
        self._publishers.append(publisher)
        return publisher

    def create_subscription(
        self,
        msg_type: type,
        topic: str,
        callback: Callable[..., Any],
        qos_profile: QoSProfile | int,
        *,
        callback_group: object = None,
        raw: bool = False,
        **options: object,
    ) -> Subscription:
        """Call ``callback(msg)`` (or ``callback(msg, info)``) with each message on ``topic``,
        from an executor spinning this node."""
        self._check_type(msg_type)
        if not callable(callback):
            raise TypeError(f"callback must be callable, got {type(callback).__name__}")
        subscription = Subscription(
            self._graph,
            msg_type,
            self.resolve_topic_name(topic),
            callback,
            as_profile(qos_profile),
            logger=self._logger,
            now_ns=lambda: self._clock.now().nanoseconds,
            callback_group=callback_group,
            raw=raw,
            internal=bool(options.get("_internal", False)),
        )
        self._subscriptions.append(subscription)
        return subscription

    @staticmethod
    def _check_type(msg_type: type) -> None:
        if not isinstance(msg_type, type) or not hasattr(msg_type, "_fields_and_field_types"):
            raise TypeError(f"{msg_type!r} is not a ROS message type")

    def get_topic_names_and_types(self, no_demangle: bool = False) -> list[tuple[str, list[str]]]:
        """Every topic with a publisher or subscription, and its types."""
        return self._graph.names_and_types()

    def count_publishers(self, topic_name: str) -> int:
        """How many publishers ``topic_name`` has."""
        return self._graph.count(self.resolve_topic_name(topic_name), publishers=True)

    def count_subscribers(self, topic_name: str) -> int:
        """How many subscriptions ``topic_name`` has."""
        return self._graph.count(self.resolve_topic_name(topic_name), publishers=False)

    # -- time ---------------------------------------------------------------------------------

    def create_timer(
        self,
        timer_period_sec: float,
        callback: Callable[[], Any] | None,
        callback_group: object = None,
        clock: Clock | None = None,
        autostart: bool = True,
    ) -> Timer:
        """Call ``callback()`` every ``timer_period_sec`` seconds of sim time, first one period
        from now (module :mod:`~baobab.nav.ros.rclpy.timer`)."""
        period_ns = int(float(timer_period_sec) * S_TO_NS)
        timer = Timer(
            callback,
            callback_group,
            period_ns,
            self._clock if clock is None else clock,
            graph=self._graph,
            autostart=autostart,
        )
        self._timers.append(timer)
        return timer

    def create_rate(self, frequency: float, clock: Clock | None = None) -> Rate:
        """A rate of ``frequency`` Hz whose ``sleep()`` waits on sim time.

        Raises:
            ValueError: a frequency that is not positive.
        """
        if frequency <= 0:
            raise ValueError("frequency must be > 0")
        timer = Timer(
            None,
            None,
            int(S_TO_NS / frequency),
            self._clock if clock is None else clock,
            graph=self._graph,
        )
        self._timers.append(timer)
        return Rate(timer, wait=lambda due, ready: waiting.wait(due, ready, what="Rate.sleep()"))

    # -- parameters ---------------------------------------------------------------------------

    def declare_parameter(
        self,
        name: str,
        value: Any = None,
        descriptor: ParameterDescriptor | None = None,
        ignore_override: bool = False,
    ) -> Parameter:
        """Declare a parameter (:mod:`baobab.nav.ros.rclpy._parameters` has the rules)."""
        return self._parameters.declare(name, value, descriptor, ignore_override)

    def declare_parameters(
        self, namespace: str, parameters: Sequence[tuple[Any, ...]], ignore_override: bool = False
    ) -> list[Parameter]:
        """Declare ``namespace.name`` for each ``(name[, value[, descriptor]])``."""
        return self._parameters.declare_many(namespace, parameters, ignore_override)

    def undeclare_parameter(self, name: str) -> None:
        """Remove a declared parameter."""
        self._parameters.undeclare(name)

    def has_parameter(self, name: str) -> bool:
        """True when ``name`` is declared."""
        return self._parameters.has(name)

    def get_parameter(self, name: str) -> Parameter:
        """The declared parameter ``name``."""
        return self._parameters.get(name)

    def get_parameters(self, names: Sequence[str]) -> list[Parameter]:
        """The declared parameters ``names``, in order."""
        return [self._parameters.get(name) for name in names]

    def get_parameter_or(self, name: str, alternative_value: Parameter | None = None) -> Parameter:
        """``name``, or ``alternative_value`` when it is not declared."""
        return self._parameters.get_or(name, alternative_value)

    def get_parameters_by_prefix(self, prefix: str) -> dict[str, Parameter]:
        """The parameters under ``prefix.``, by the rest of their names."""
        return self._parameters.by_prefix(prefix)

    def set_parameters(self, parameter_list: Sequence[Parameter]) -> list[SetParametersResult]:
        """Set each parameter; one result each (a refused one keeps its value)."""
        return self._parameters.set_many(list(parameter_list))

    def set_parameters_atomically(self, parameter_list: Sequence[Parameter]) -> SetParametersResult:
        """Set all the parameters or none."""
        result: SetParametersResult = self._parameters.set_many(
            list(parameter_list), atomically=True
        )[0]
        return result

    def describe_parameter(self, name: str) -> ParameterDescriptor:
        """The descriptor of ``name``."""
        return self._parameters.describe(name)

    def describe_parameters(self, names: Sequence[str]) -> list[ParameterDescriptor]:
        """The descriptors of ``names``."""
        return [self._parameters.describe(name) for name in names]

    def set_descriptor(
        self, name: str, descriptor: ParameterDescriptor, alternative_value: object = None
    ) -> None:
        """Replace the descriptor of ``name``."""
        self._parameters.set_descriptor(name, descriptor)

    def add_on_set_parameters_callback(self, callback: SetCallback) -> SetCallback:
        """Run ``callback(parameters) -> SetParametersResult`` before each set (and declare)."""
        self._parameters.add_callback(callback)
        return callback

    def remove_on_set_parameters_callback(self, callback: SetCallback) -> None:
        """Stop running ``callback``."""
        self._parameters.remove_callback(callback)

    # -- destroying ---------------------------------------------------------------------------

    def destroy_publisher(self, publisher: Publisher) -> bool:
        """Destroy one of the node's publishers; False if it is not the node's."""
        return self._destroy(self._publishers, publisher)

    def destroy_subscription(self, subscription: Subscription) -> bool:
        """Destroy one of the node's subscriptions; False if it is not the node's."""
        return self._destroy(self._subscriptions, subscription)

    def destroy_timer(self, timer: Timer) -> bool:
        """Destroy one of the node's timers; False if it is not the node's."""
        return self._destroy(self._timers, timer)

    def destroy_rate(self, rate: Rate) -> bool:
        """Destroy a rate made by :meth:`create_rate`."""
        rate.destroy()
        return True

    @staticmethod
    def _destroy(entities: list[Any], entity: Any) -> bool:
        if entity not in entities:
            return False
        entities.remove(entity)
        entity.destroy()
        return True

    def destroy_node(self) -> None:
        """Release the node and everything it made; a second call does nothing."""
        if self._destroyed:
            return
        self._destroyed = True
        entities: list[Publisher | Subscription | Timer] = [
            *self._publishers,
            *self._subscriptions,
            *self._timers,
        ]
        for entity in entities:
            entity.destroy()
        self._publishers, self._subscriptions, self._timers = [], [], []
        if self.executor is not None:
            self.executor.remove_node(self)
        self._context.untrack_node(self)

    def _spin_once(self, timeout_sec: float | None) -> None:
        """What ``rclpy.spin_once(node)`` does outside a run after the node's ready callbacks:
        nothing for a plain node; a navigator advances its simulation."""

    # -- not modelled -------------------------------------------------------------------------

    def _unsupported(self, what: str) -> NoReturn:
        raise UnsupportedRosFeatureError(
            f"Node.{what}() is not supported: baobab models topics, timers and parameters, "
            "not services or actions"
        )

    def create_client(self, *args: object, **kwargs: object) -> NoReturn:
        """Not supported (no ROS services)."""
        self._unsupported("create_client")

    def create_service(self, *args: object, **kwargs: object) -> NoReturn:
        """Not supported (no ROS services)."""
        self._unsupported("create_service")

    def __enter__(self) -> Node:
        return self

    def __exit__(self, *exc: object) -> None:
        self.destroy_node()
