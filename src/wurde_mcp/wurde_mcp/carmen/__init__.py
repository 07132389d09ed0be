"""CARMEN's parameter server: carmen.ini (:mod:`.ini`), ``param_daemon`` (:mod:`.daemon`) and
``param_tool`` (:mod:`.tool`).  Programs read the parameters with
:class:`wurde_core.carmen_param.CarmenParams` (Programming with CARMEN, 6)."""

from .ini import (
    ALL_ROBOTS,
    EXPERT,
    SEARCH_PATH,
    Entry,
    IniFile,
    IniWarning,
    Section,
    choose_robot,
    find_ini,
    read_ini,
    robots,
)

__all__ = ['ALL_ROBOTS', 'EXPERT', 'SEARCH_PATH', 'Entry', 'IniFile', 'IniWarning', 'Section',
           'choose_robot', 'find_ini', 'read_ini', 'robots']
