"""The mission language: a YAML file -> a validated :class:`Mission` -> a py_trees tree.

- :mod:`.loader`: :func:`load_mission` (every mistake a located ``MissionError``, exit 2),
  :class:`Mission`; :mod:`.bundled_missions`: MISSION as a path or a bundled name.
- :mod:`.models`: pydantic models of the file's top level, events and ``expect:``;
  :mod:`.params`: typed ``params`` and ``${name}`` substitution; :mod:`.tree_parser`: the
  ``tree:`` and ``subtrees:``, node by node against the behaviour registry
  (:mod:`baobab.behaviours`); :mod:`.cross_checks`: events and expectations against the robot
  and the world; :mod:`.error_codes` and :mod:`.metric_names`: what ``expect:`` may name.
- :mod:`.compiler`: :func:`compile_mission`, the tree wired to capability ports.
- :mod:`.json_schema`: ``baobab schema``; :mod:`.tree_export`: unicode, Graphviz dot and
  BehaviorTree.CPP XML, with :mod:`.btcpp_ports` and :mod:`.btcpp_limits`; :mod:`.btcpp_log`:
  Groot2's ``.btlog`` replay format.
- :mod:`.errors`: :class:`MissionError` and readable pydantic errors.

Loading a mission loads no physics: ``baobab validate`` stays well under half a second.
"""
