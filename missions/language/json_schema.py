"""The JSON Schema of the mission format, assembled from the pydantic models and the registry.

The top level, events and expectations come from
:class:`~baobab.missions.language.models.MissionFile`;
each node type's parameters come from its registered model, so the schema cannot drift from
what the loader accepts. Two loader features need care:

- short forms: a node's value may be its parameter mapping, a bare shorthand value, a list of
  children, a single child node, or empty;
- ``${param}`` substitution: wherever a number, boolean or fixed word is expected, a string
  that is exactly ``${name}`` is also allowed, and a name-like string may contain ``${name}``
  (the loader checks the substituted value).

The schema is a guide for editors; the loader remains the judge (it also checks locations,
capabilities, free space and everything that needs the world).
"""

from __future__ import annotations

from typing import Any

from baobab.behaviours.builtin import default_registry
from baobab.behaviours.registry import (
    NODE_SCHEMA_MARKER,
    BehaviourType,
    NodeKind,
    Registry,
)
from baobab.missions.language.models import MissionFile

SCHEMA_DIALECT = "https://json-schema.org/draft/2020-12/schema"
PARAM_REF = {"type": "string", "pattern": r"^\$\{[A-Za-z_][A-Za-z0-9_]*\}$"}
_NODE_REF = {"$ref": "#/$defs/Node"}
_PARAM_REF_REF = {"$ref": "#/$defs/ParamRef"}
_PARAM_TEXT_REF = {"$ref": "#/$defs/ParamText"}
_SCALAR_TYPES = ("number", "integer", "boolean")
_SCHEMA_MAPS = ("properties", "patternProperties", "$defs")


def mission_json_schema(registry: Registry | None = None) -> dict[str, Any]:
    """The JSON Schema (draft 2020-12) of a mission file."""
    registry = registry or default_registry()
    schema = MissionFile.model_json_schema(ref_template="#/$defs/{model}")
    definitions: dict[str, Any] = schema.pop("$defs", {})
    variants = [_node_variant(behaviour, definitions) for behaviour in registry]
    definitions["Node"] = {
        "description": "one behaviour-tree node: a single-key mapping {type: parameters}",
        "type": "object",
        "minProperties": 1,
        "maxProperties": 1,
        "anyOf": variants,
    }
    definitions = {name: _allow_param_refs(_resolve_markers(d)) for name, d in definitions.items()}
    definitions["ParamRef"] = dict(PARAM_REF, description="${name}: a parameter's value")
    definitions["ParamText"] = {
        "type": "string",
        "pattern": r"\$\{[A-Za-z_][A-Za-z0-9_]*\}",
        "description": "text with ${name} inside",
    }
    from baobab.nav.collision_monitor_params import parameters_schema

    schema["properties"]["collision_monitor"] = parameters_schema()
    body = _allow_param_refs(_resolve_markers(schema))
    return {
        "$schema": SCHEMA_DIALECT,
        "title": "baobab mission",
        **{key: value for key, value in body.items() if key != "title"},
        "$defs": definitions,
    }


def _node_variant(behaviour: BehaviourType, definitions: dict[str, Any]) -> dict[str, Any]:
    params = behaviour.params.model_json_schema(ref_template="#/$defs/{model}")
    definitions.update(params.pop("$defs", {}))
    params.pop("title", None)
    options: list[dict[str, Any]] = [params]
    required = params.get("required", [])
    if not required:
        options.append({"type": "null"})
    shorthand = behaviour.shorthand
    if behaviour.kind is NodeKind.DECORATOR and shorthand == "child":
        options.append(_NODE_REF)
    elif shorthand is not None:
        options.append(params["properties"][shorthand])
    value: dict[str, Any] = {"anyOf": options} if len(options) > 1 else params
    return {
        "type": "object",
        "description": behaviour.description,
        "properties": {behaviour.name: value},
        "required": [behaviour.name],
        "additionalProperties": False,
    }


def _resolve_markers(value: Any) -> Any:
    """Replace the node marker by a reference to ``#/$defs/Node``; plain-text descriptions.

    Descriptions come from docstrings, whose reStructuredText quotes editors would show as is.
    """
    if isinstance(value, dict):
        if value.get(NODE_SCHEMA_MARKER):
            return dict(_NODE_REF)
        converted = {key: _resolve_markers(item) for key, item in value.items()}
        if isinstance(converted.get("description"), str):
            converted["description"] = converted["description"].replace("``", "")
        return converted
    if isinstance(value, list):
        return [_resolve_markers(item) for item in value]
    return value


def _allow_param_refs(value: Any) -> Any:
    """Let every number, boolean or fixed-word schema also accept ``${name}``."""
    if isinstance(value, list):
        return [_allow_param_refs(item) for item in value]
    if not isinstance(value, dict):
        return value
    converted: dict[str, Any] = {}
    for key, item in value.items():
        if key in _SCHEMA_MAPS and isinstance(item, dict):
            converted[key] = {name: _allow_param_refs(sub) for name, sub in item.items()}
        else:
            converted[key] = _allow_param_refs(item)
    kind = converted.get("type")
    if kind in _SCALAR_TYPES or "enum" in converted or "const" in converted:
        alternative = _PARAM_REF_REF
    elif kind == "string" and "pattern" in converted:
        alternative = _PARAM_TEXT_REF
    else:
        return converted
    notes = {k: converted.pop(k) for k in ("default", "description", "title") if k in converted}
    return {"anyOf": [converted, alternative], **notes}
