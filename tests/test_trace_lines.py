"""Trace lines: the direct writer of flat records gives exactly ``json.dumps``'s text."""

from __future__ import annotations

import enum
import hashlib
import json
import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from baobab.missions.run.trace import DECIMALS, Trace, _float_text, jsonable

_scalars = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.floats(min_value=-1e-5, max_value=1e-5),
    st.integers(),
    st.text(),
    st.booleans(),
    st.none(),
)
_values = st.one_of(
    _scalars,
    st.dictionaries(st.text(), _scalars, max_size=4),  # a feedback record's scalars
    st.dictionaries(st.text(), st.dictionaries(st.text(), _scalars, max_size=2), max_size=2),
)


def _reference(record: dict[str, object]) -> str:
    return json.dumps(jsonable(record), separators=(",", ":"), ensure_ascii=False)


@settings(max_examples=500, deadline=None)
@given(
    time=st.floats(min_value=0.0, max_value=1e6),
    kind=st.text(),
    fields=st.dictionaries(st.text(), _values, max_size=6),
)
def test_flat_records_are_written_as_json_dumps_writes_them(
    time: float, kind: str, fields: dict[str, object]
) -> None:
    fields.pop("t", None)
    fields.pop("type", None)
    trace = Trace()
    trace.add(time, kind, **fields)
    assert trace.lines == [_reference({"t": time, "type": kind, **fields})]


class _Mode(enum.Enum):
    FAST = "fast"


def test_records_with_other_values_still_go_through_jsonable() -> None:
    trace = Trace()
    trace.add(1.0, "event", mode=_Mode.FAST, xy=np.array([0.1234567, math.inf]), n=np.int64(3))
    assert trace.lines == ['{"t":1.0,"type":"event","mode":"fast","xy":[0.123457,"inf"],"n":3}']


def test_feedback_records_are_written_directly_as_json_dumps_writes_them() -> None:
    trace = Trace()
    feedback = {"distance_remaining": 1.23456789, "recoveries": 0, "note": "é\n", "done": False}
    trace.add(2.5, "feedback", node="go", feedback=feedback)
    trace.add(2.5, "feedback", node="go", feedback={1: 2.0}, other={"x": np.float64(0.5)})
    assert trace.lines == [
        _reference({"t": 2.5, "type": "feedback", "node": "go", "feedback": feedback}),
        '{"t":2.5,"type":"feedback","node":"go","feedback":{"1":2.0},"other":{"x":0.5}}',
    ]


@settings(max_examples=3000, deadline=None)
@given(
    number=st.one_of(
        st.floats(min_value=-2e9, max_value=2e9),
        st.floats(min_value=1e9, max_value=1e12),  # past the 15 digits the fast text needs
        st.floats(min_value=-2e-4, max_value=2e-4),
        st.sampled_from([1e-4, -1e-4, 9.9999995e-5, 1e9, 999999999.9999996, 1 / 128, 2.5, 3.0]),
        st.integers(-(10**9), 10**9).map(lambda n: n / 128),  # exact ties at the 7th decimal
    )
)
def test_float_texts_are_repr_of_the_rounded_float(number: float) -> None:
    rounded = round(number, DECIMALS)
    assert _float_text(number) == (repr(rounded) if rounded else "0.0")


def test_the_digest_is_the_hash_of_the_text_whenever_it_is_asked() -> None:
    trace = Trace()
    assert trace.digest == hashlib.sha256(b"").hexdigest()
    for step in range(30):
        trace.add(0.1 * step, "pose", x=step / 7, note="é")
        if step % 8 == 0:
            assert trace.digest == hashlib.sha256(trace.text().encode("utf-8")).hexdigest()
    assert trace.digest == hashlib.sha256(trace.text().encode("utf-8")).hexdigest()
