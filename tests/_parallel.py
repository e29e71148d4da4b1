"""The suite's units of work under pytest-xdist (``make test``: ``-n 2 --dist loadscope``).

Every test module is one unit, run whole by one worker, so that a
module-scoped fixture is made once. The modules that share an expensive
session fixture form one unit together (``SHARED``), so that the fixture is
made once per run, not once per worker. The units that take longest start
first (``LONGEST``), so that no worker is left alone with a long one at the end.

The grouping is done by the scheduler (``pytest_xdist_make_scheduler`` in
``tests/conftest.py``), not by ``xdist_group`` marks, which pytest 9.2 no longer
lets pytest-xdist 3.8 apply.
"""

from __future__ import annotations

from collections import OrderedDict
from typing import Any

from xdist.scheduler import LoadScopeScheduling

#: Test modules that share an expensive session fixture, or a resource of the
#: machine, and the unit they form: the executed notebooks and the site built
#: from them; the wheel and the fresh environments that install it; the runs of
#: LinuxCNC, whose realtime environment (rtapi_app) is one per machine, so a
#: halrun beside a linuxcnc session fails (both modules use the session fixture
#: ``run`` of tests/controller/conftest.py, made once).
SHARED = {
    "tests/test_notebooks.py": "notebooks",
    "tests/test_docs.py": "notebooks",
    "tests/test_wheel.py": "wheel",
    "tests/test_bare_install.py": "wheel",
    "tests/controller/test_configuration.py": "linuxcnc",
    "tests/controller/test_stream.py": "linuxcnc",
}
#: The units that take longest, longest first (``make test`` lists the slowest tests).
LONGEST = (
    "notebooks",
    "linuxcnc",
    "tests/sweep/test_runner.py",
    "tests/test_own_design.py",
    "wheel",
    "tests/sweep/test_pool.py",
    "tests/test_lint.py",
    "tests/hostile/test_outputs.py",
    "tests/planning/test_plan.py",
    "tests/hostile/test_interrupts.py",
    "tests/test_docs_pages.py",
)


def work_unit(nodeid: str) -> str:
    """The unit of work of the test ``nodeid``: its module, or its module's group."""
    module = nodeid.split("::", 1)[0]
    return SHARED.get(module, module)


class ModuleUnits(LoadScopeScheduling):
    """pytest-xdist's ``loadscope`` with the suite's units, the longest first."""

    def __init__(self, config: Any, log: Any = None) -> None:
        super().__init__(config, log)
        self._ordered = False

    def _split_scope(self, nodeid: str) -> str:
        return work_unit(nodeid)

    def _assign_work_unit(self, node: Any) -> None:
        if not self._ordered:  # the queue is whole once the first unit is handed out
            rank = {unit: i for i, unit in enumerate(LONGEST)}
            units = sorted(self.workqueue.items(), key=lambda u: rank.get(u[0], len(LONGEST)))
            self.workqueue = OrderedDict(units)
            self._ordered = True
        super()._assign_work_unit(node)
