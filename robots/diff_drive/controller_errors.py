"""The codes of failed base-controller tasks (go-to-goal, Bug2), light enough for validation."""

from __future__ import annotations

import enum


class BaseControllerError(enum.IntEnum):
    """Why a base-controller task failed (``TaskOutcome.error_code``; 8xx, unused by Nav2)."""

    NONE = 0
    UNKNOWN = 800
    FAILED_TO_MAKE_PROGRESS = 801
