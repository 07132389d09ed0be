"""What an interface file says, after validation: the input of every generator."""

from __future__ import annotations

from dataclasses import dataclass, field


@dataclass(frozen=True)
class Member:
    """One ``<data>`` element that survives into the generated structure.

    ``type`` is the canonical WURDE type name (a scalar, a built-in, or a ``type`` section of the
    same file); ``count_member`` is the WURDE name of the dropped count member for arrays.
    """

    name: str
    xml_name: str
    type: str
    is_array: bool = False
    count_member: str | None = None
    line: int = 0


@dataclass(frozen=True)
class StructType:
    """A ``<type>`` section: a structure usable by the info and publish sections."""

    name: str
    members: tuple[Member, ...]
    line: int = 0


@dataclass(frozen=True)
class Interface:
    """A whole interface definition file."""

    name: str
    version: str
    author: str
    description: str
    types: tuple[StructType, ...] = ()
    info: tuple[Member, ...] | None = None
    publish: tuple[Member, ...] | None = None
    path: str = ''
    line: int = 0
    dropped: dict[str, tuple[str, ...]] = field(default_factory=dict)

    @property
    def data_message(self) -> str:
        """Name of the generated data message (``publish`` section)."""
        return f'{self.name}Data'

    @property
    def info_message(self) -> str:
        """Name of the generated info message (``info`` section; requests use it too)."""
        return f'{self.name}Info'
