"""The declaration of settings (:mod:`bristlecrawler.settings`), under the name the FE
core's option objects import it by."""

from bristlecrawler.settings import (
    REQUIRED,
    Settings,
    check_settings,
    compose,
    own_defaults,
    renamed,
    setting,
    setting_of,
    settings_of,
    structural_settings,
)

__all__ = [
    "REQUIRED",
    "Settings",
    "check_settings",
    "compose",
    "own_defaults",
    "renamed",
    "setting",
    "setting_of",
    "settings_of",
    "structural_settings",
]
