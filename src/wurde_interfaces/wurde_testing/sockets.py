"""Which local addresses listen on a TCP port: a server of ours must bind 127.0.0.1 unless told
otherwise (issue 16), and a test checks it from the kernel's own tables."""

from __future__ import annotations

import pathlib

__all__ = ['LOOPBACK', 'listening_addresses']

#: 127.0.0.1 as /proc/net/tcp writes it (hex, little-endian).
LOOPBACK = '0100007F'


def listening_addresses(port: int) -> list[str]:
    """Local addresses (hex, as /proc/net/tcp and tcp6 write them) listening on ``port``.

    :param port: the TCP port.
    """
    found = []
    for table in ('/proc/net/tcp', '/proc/net/tcp6'):
        for line in pathlib.Path(table).read_text().splitlines()[1:]:
            local, state = line.split()[1], line.split()[3]
            address, _, hex_port = local.partition(':')
            if int(hex_port, 16) == port and state == '0A':      # TCP_LISTEN
                found.append(address)
    return found
