"""Mission items in pytest's JUnit XML report, in a form its xunit2 schema allows.

pytest's default ``junit_family`` is xunit2, whose schema (the Jenkins xunit plugin's
``junit-10.xsd``) allows no ``<properties>`` inside a ``<testcase>``: strict CI parsers refuse
such a file. So a mission's facts go in its testcase's ``<system-out>``, one ``key: value`` a
line (result, sim time in s, trace digest, seed, baseline, run folder), and the testcase is
named so that Jenkins-style views, which split ``classname`` at its last dot, read it as the
mission's folder and name::

    <testcase classname="missions" name="walls_go_to_goal" time="3.021">
      <system-out>result: SUCCEEDED
    sim_time: 14.700
    ...</system-out>
    </testcase>

The facts travel from the item to the report writer as the item's ``baobab`` report section
(:data:`FACTS_SECTION`), which pytest-xdist carries from its workers to the controller, where
the report is written. pytest offers no public way to add to a testcase element, so this
module uses the report writer pytest keeps in ``config.stash`` (``_pytest.junitxml``); the
plugin's tests validate the file against the schema, so a change there shows.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import PurePosixPath

import pytest
from _pytest import junitxml

FACTS_SECTION = "baobab"
"""The report section (``item.add_report_section("call", FACTS_SECTION, text)``) of facts."""
MISSION_LABEL = "mission "
"""How a mission item's ``reportinfo`` label begins (a broken one's: ``invalid mission ``)."""
_LABELS = (MISSION_LABEL, f"invalid {MISSION_LABEL}")
_SECTION_TITLE = f"Captured {FACTS_SECTION} call"


def format_facts(facts: dict[str, str]) -> str:
    """The ``key: value`` lines of a mission run's facts."""
    return "".join(f"{key}: {value}\n" for key, value in facts.items())


def register(config: pytest.Config) -> None:
    """Write mission items the xunit2 way when this process writes a JUnit report."""
    xml = config.stash.get(junitxml.xml_key, None)
    if xml is not None:
        root_name = config.rootpath.name or "missions"
        config.pluginmanager.register(JunitMissions(xml, root_name), "baobab-junit")


class JunitMissions:
    """Names each mission's testcase and gives it its facts, before pytest's writer sees it."""

    def __init__(self, xml: junitxml.LogXML, root_name: str) -> None:
        """``xml``: pytest's ``LogXML``; ``root_name``: the class of missions in the rootdir."""
        self.xml = xml
        self.root_name = root_name

    @pytest.hookimpl(tryfirst=True)
    def pytest_runtest_logreport(self, report: pytest.TestReport) -> None:
        """On each report that makes or extends a testcase, name it and add the facts."""
        if not report.location[2].startswith(_LABELS):
            return
        if report.passed and report.when != "call":
            return  # pytest's writer opens no testcase for these: neither does this
        reporter = self.xml.node_reporter(report)
        reporter.add_attribute("classname", self._classname(report.nodeid))
        facts = "".join(text for title, text in report.sections if title == _SECTION_TITLE)
        if facts and report.when == "call":
            element = ET.Element("system-out")
            element.text = junitxml.bin_xml_escape(facts)
            reporter.append(element)

    def _classname(self, nodeid: str) -> str:
        """The mission file's folder, dotted (``missions/nav/a.yaml`` -> ``missions.nav``)."""
        folder = PurePosixPath(nodeid.split("::", 1)[0]).parent.parts
        parts = [part.replace(".", "_") for part in folder if part != ".."] or [self.root_name]
        prefix = self.xml.prefix
        return ".".join([prefix, *parts] if prefix else parts)
