"""Every behaviour-tree node type a mission may use: its parameters, its factory, its py_trees.

- :mod:`.registry`: the mechanism: :class:`~.registry.BehaviourType` (one node type: name,
  kind, parameter model, factory, capability, shorthand), :class:`~.registry.Registry`,
  :class:`~.registry.NodeParams`, :class:`~.registry.BuildRequest`.
- :mod:`.builtin`: :func:`~.builtin.default_registry`, every node module's ``NODE_TYPES``
  in order. The node modules: :mod:`.control_nodes` (composites, decorators, subtrees),
  :mod:`.common_nodes` (wait, elapsed, constants), :mod:`.navigation_nodes` (Nav2 tasks and
  the tutorial base controllers), :mod:`.progress_nodes` (the forward-progress rule),
  :mod:`.arm_nodes` (tool moves, gripper).
- :mod:`.ports`: the capability ports leaves talk to (Protocols) and
  :class:`~.ports.Capabilities`; :mod:`.poses`: pose forms in node parameters and the
  :class:`~.poses.MissionScope` they resolve in.
- The py_trees classes the factories build, imported only when a tree is built (validation
  loads no py_trees): :mod:`.actions`, :mod:`.conditions`, :mod:`.decorators`, :mod:`.timing`,
  :mod:`.progress` (:mod:`baobab.nav.direct_tick` ticks a tree of them without py_trees'
  generators).

Adding a node type is one module with its parameter model, factory and ``NODE_TYPES``, listed
in :data:`.builtin.NODE_MODULES` (see ``docs/architecture.md``).
"""
