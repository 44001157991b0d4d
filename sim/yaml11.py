"""Where YAML 1.1, which PyYAML reads, and YAML 1.2 disagree: refused rather than guessed.

YAML 1.2 (and most tools people check their files with) reads ``off`` and ``yes`` as text,
``1:30`` as text and ``010`` as ten, and breaks lines only at ``\\n``, ``\\r\\n`` and ``\\r``;
PyYAML reads false, true, 90 and eight, and also breaks lines at U+0085, U+2028 and U+2029
(a comment then ends in the middle of an editor's line). A file that means one thing to its
author's editor and another to baobab is refused, with the two ways to write what was meant.
"""

from __future__ import annotations

import re
from typing import Any

import yaml

from baobab.sim.errors import clip
from baobab.sim.text_positions import YAML11_ONLY_BREAKS
from baobab.sim.yaml_limits import libyaml_available

_BOOL_TAG = "tag:yaml.org,2002:bool"
_INT_TAG = "tag:yaml.org,2002:int"
_FLOAT_TAG = "tag:yaml.org,2002:float"
_YAML11_BOOLEAN_WORDS = frozenset(
    word for base in ("yes", "no", "on", "off") for word in (base, base.title(), base.upper())
)
_OCTAL = re.compile(r"^[-+]?0[0-7_]+$")


def scalar_surprise(tag: str, text: str, value: Any) -> str | None:
    """Why a scalar PyYAML resolved to ``tag`` and ``value`` means something else in YAML 1.2.

    Returns:
        The message of a located error, or None when both read the same.
    """
    if tag == _BOOL_TAG and text in _YAML11_BOOLEAN_WORDS:
        word = "true" if value else "false"
        return (
            f"'{text}' reads as {word} in YAML 1.1; write {word} for a yes/no value, or quote "
            f"it ('{text}') for a name or text"
        )
    if tag in (_INT_TAG, _FLOAT_TAG) and ":" in text:
        number = f"{value:g}" if isinstance(value, float) else str(value)
        return (
            f"'{clip(text)}' reads as the base-60 number {number} in YAML 1.1; write {number} "
            f"if you mean that number, or quote it ('{clip(text)}') for text"
        )
    if tag == _INT_TAG and _OCTAL.match(text):
        sign = "-" if text.startswith("-") else ""
        decimal = sign + (text.replace("_", "").lstrip("+-").lstrip("0") or "0")
        return (
            f"'{clip(text)}' reads as the octal number {value} in YAML 1.1; write {decimal} "
            f"without the leading zero, or quote it ('{clip(text)}') for text"
        )
    return None


_YAML11_BREAK = re.compile(f"[{''.join(YAML11_ONLY_BREAKS)}]")
_BREAK_NAMES = {"\x85": "U+0085 (next line)", "\u2028": "U+2028 (line separator)"}


def unquoted_break(text: str) -> tuple[int, str] | None:
    """The first U+0085, U+2028 or U+2029 outside a quoted string: (index, message), or None.

    Inside quotes PyYAML keeps the character as part of the string, as YAML 1.2 does.
    """
    quoted: list[tuple[int, int]] = []
    try:
        loader = yaml.CSafeLoader if libyaml_available() else yaml.SafeLoader
        for token in yaml.scan(text, Loader=loader):
            if isinstance(token, yaml.ScalarToken) and token.style in ("'", '"'):
                quoted.append((token.start_mark.index, token.end_mark.index))
    except yaml.YAMLError:
        pass  # the loader reports the syntax error; the breaks before it were checked
    for found in _YAML11_BREAK.finditer(text):
        index, char = found.start(), found.group()
        if not any(start <= index < end for start, end in quoted):
            name = _BREAK_NAMES.get(char, "U+2029 (paragraph separator)")
            return index, (
                f"character {name} outside quotes: YAML 1.1 breaks the line there, YAML 1.2 "
                f"does not; remove it, or write it inside double quotes as \\u{ord(char):04x}"
            )
    return None
