"""Turn a validated :class:`~wurde_idl.model.Interface` into ROS 2 ``.msg`` files.

For interface ``X`` (seed: WURDE Programming Guide 3.3 and chapter 2): ``XData.msg`` from the
``publish`` section, ``XInfo.msg`` from the ``info`` section (requests from consumers travel in the
same type) and one message per ``type`` section.  Data and Info messages start with the common
header (source tag and timestamp); Info messages also say which members an event sets and which
locks the supplier holds (the Writable access control of guide 3.2.4).
"""

from __future__ import annotations

from .model import Interface, Member
from .types import BUILTIN_ENUMS, BUILTIN_MESSAGES, BUILTIN_PACKAGE, SCALARS

_DATA_HEADER = (
    f'# Common header: source tag (auto-tag) and timestamp (auto-timestamp).\n'
    f'{BUILTIN_PACKAGE}/Header header\n'
)
_INFO_HEADER = _DATA_HEADER + (
    '# Members this event sets, by ROS field name; empty means every member.\n'
    'string[] set_fields\n'
    '# Locks the supplier holds on the writable members (Writable access control).\n'
    f'{BUILTIN_PACKAGE}/Lock[] locks\n'
)


def ros_type(member: Member, package: str) -> str:
    """The ``.msg`` type of ``member`` in a message of ``package``.

    :param member: a validated member.
    :param package: the ROS package the message belongs to (for a ``<type>`` of the same file).
    """
    if member.type in SCALARS:
        base = SCALARS[member.type].ros_type
    elif member.type in BUILTIN_MESSAGES or member.type in BUILTIN_ENUMS:
        base = f'{BUILTIN_PACKAGE}/{member.type}'
    else:
        base = f'{package}/{member.type}'
    return f'{base}[]' if member.is_array else base


def _fields(members: tuple[Member, ...] | None, package: str) -> str:
    lines = []
    for member in members or ():
        note = f'  # array, length given by WURDE member "{member.count_member}"' \
            if member.is_array else ''
        renamed = f'  # WURDE name "{member.xml_name}"' \
            if member.xml_name != member.name and not note else ''
        lines.append(f'{ros_type(member, package)} {member.name}{note}{renamed}')
    return ''.join(f'{line}\n' for line in lines)


def _banner(interface: Interface, what: str, depends_digest: str) -> str:
    digest = f'# Built against dependency interfaces {depends_digest[:16]}.\n' \
        if depends_digest else ''
    return (f'# {what} of WURDE interface {interface.name} {interface.version}.\n'
            f'# Generated from {interface.path.rsplit("/", 1)[-1]} by wurde_idl; do not edit.\n'
            + digest)


def messages(interface: Interface, package: str, depends_digest: str = '') -> dict[str, str]:
    """Return ``{message name: .msg text}`` for every message of ``interface``.

    :param interface: a validated interface.
    :param package: the ROS package the messages belong to.
    :param depends_digest: a digest of the dependencies' interfaces, written (its first 16
        characters) into every message's banner; empty: none.
    """
    result = {
        interface.data_message: _banner(interface, 'Data (publish section)', depends_digest)
        + _DATA_HEADER + _fields(interface.publish, package),
        interface.info_message: _banner(interface, 'Info (info section; also requests)', depends_digest)
        + _INFO_HEADER + _fields(interface.info, package),
    }
    for struct in interface.types:
        result[struct.name] = (_banner(interface, f'Type {struct.name}', depends_digest)
                               + _fields(struct.members, package))
    return result
