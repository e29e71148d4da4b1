"""Start-up hook of the commands that the interrupt tests stop in the middle of a write.

On the ``PYTHONPATH`` of such a command only (``PAUSE_ENV`` names a file): just
before the command puts a finished output directory in place, it creates that
file and then sleeps until a signal ends it. The test signals it there, at a
known point of the write, instead of racing the write to its end.
"""

from __future__ import annotations

import os
import time
from pathlib import Path
from typing import Any

#: Environment variable naming the file that says the command is paused.
PAUSE_ENV = "ORTHOGLIDE_TEST_PAUSED_FILE"
#: What names the package's temporary siblings (``orthoglide_pin._paths.TEMP_TAG``).
TEMP_TAG = "orthoglide-tmp"

_paused = os.environ.get(PAUSE_ENV)
if _paused:
    _replace = os.replace

    def _pausing_replace(src: Any, dst: Any, *args: Any, **kwargs: Any) -> None:
        if TEMP_TAG in os.fspath(src) and os.path.isdir(src):
            Path(_paused).touch()
            while True:  # until a signal ends the command
                time.sleep(60.0)
        _replace(src, dst, *args, **kwargs)

    os.replace = _pausing_replace
