"""Telling a restarted sender from the one before: a consumer's view of who sends a stream.

A module that keeps state derived from a stream in the sender's own terms (odometry counted from
zero by a base process, a DMU's integration) must know when the process behind the stream is a
new one.  Every WURDE message says which process sent it (``header.session``, drawn at the
process's start, :data:`wurde_core.channel.SESSION`) and counts them (``header.sequence``, from 1).
The count alone does not do: a consumer in latest mode (or one the MCP held Idle while the base
was restarted) may first see the new process when its count has passed the old one's, and would
take a restarted base's odometry, counted from zero, for the old frame.  The count is the rule
only for a sender that does not say its session (a recording made before it was in the header).
"""

from __future__ import annotations

from typing import Any

__all__ = ['SenderWatch']


class SenderWatch:
    """Feed it the header of every message taken from one stream (:meth:`take`)."""

    def __init__(self, session: int = 0, sequence: int = 0) -> None:
        """A watch that has seen ``session`` and ``sequence`` last.

        :param session: the sender's session when last seen (a resumed consumer's saved state; 0:
            none seen).
        :param sequence: the sender's last sequence number seen (likewise).
        """
        self.session = session
        self.sequence = sequence

    def take(self, header: Any) -> bool:
        """Whether the message of ``header`` comes from a new sender process (False for the first
        message ever seen: there is nothing to be new against).

        :param header: the message's ``wurde_interfaces/Header`` (``session``, ``sequence``).
        """
        session, sequence = int(header.session), int(header.sequence)
        if session and self.session:
            new = session != self.session
        else:
            new = 0 < sequence < self.sequence
        self.session = session or self.session
        self.sequence = sequence
        return new
