"""``live_view``: the robot's topics on a Foxglove WebSocket server, for a viewer with no ROS.

    live_view [-p PORT] [-b ADDRESS] [-t REGEX] [-x REGEX]

Every topic of the ROS graph matching ``-t`` (default all) and not ``-x`` (default ``/rosout`` and
``/parameter_events``), taken as ``record`` takes them (:mod:`.tap`), is served on Foxglove's
WebSocket protocol (foxglove-sdk) at ``ws://127.0.0.1:8765`` unless told (``-b``, ``-p``; port 0
picks a free one): Foxglove, the app or the web page, connects and shows ``/scan``, ``/odom``,
``/tf``, ``/map``, the WURDE streams... with no ROS install on the viewing side.  Each channel
carries its type's ``ros2msg`` definition and the messages as the CDR bytes that travelled
(message encoding ``cdr``), so nothing is decoded here.  A latched topic (every publisher
transient local: ``/map``, ``/tf_static``, the WURDE info channels) is sent again to each client
that subscribes to it later, as a ROS subscriber would get it.

Prints ``live_view ready on ws://HOST:PORT`` when serving; ends on SIGINT or SIGTERM.
"""

from __future__ import annotations

import argparse
import sys
import threading
import time
from typing import Any

import foxglove
from foxglove import Channel, Schema
from foxglove.websocket import ServerListener

from .tap import DEFAULT_EXCLUDE, TopicTap, run_tap, tap_node

__all__ = ['DEFAULT_PORT', 'FoxgloveSink', 'main']

#: Foxglove's own default port.
DEFAULT_PORT = 8765


class FoxgloveSink(ServerListener):
    """The Foxglove channels a :class:`~.tap.TopicTap` logs to, and the server's listener: a
    latched channel's last message goes again to whoever subscribes later."""

    def __init__(self, context: foxglove.Context) -> None:
        self.context = context
        self.channels: dict[int, Channel] = {}
        self._latched: dict[int, bytes | None] = {}
        self._lock = threading.Lock()
        self._resend: set[int] = set()
        self.subscriptions = 0

    def open_channel(self, topic: str, type_name: str, definition: str,
                     metadata: dict[str, str]) -> Channel:
        channel = Channel(topic, schema=Schema(name=type_name, encoding='ros2msg',
                                               data=definition.encode()),
                          message_encoding='cdr', context=self.context, metadata=metadata)
        self.channels[channel.id()] = channel
        if metadata.get('durability') == 'transient_local':
            self._latched[channel.id()] = None
        return channel

    def write(self, channel: Channel, data: bytes) -> None:
        channel.log(data, log_time=time.time_ns())
        if channel.id() in self._latched:
            self._latched[channel.id()] = data

    # -- foxglove.websocket.ServerListener (called in the SDK's threads) -----------------------
    def on_subscribe(self, _client: Any, channel: Any) -> None:
        with self._lock:
            self.subscriptions += 1
            self._resend.add(channel.id)

    def on_unsubscribe(self, _client: Any, _channel: Any) -> None:
        return None

    def resend(self) -> None:
        """In the tool's own thread, after the subscription is in place: the latched messages
        the new subscribers have not had."""
        with self._lock:
            ids, self._resend = self._resend, set()
        for channel_id in ids:
            data = self._latched.get(channel_id)
            if data is not None:
                self.channels[channel_id].log(data, log_time=time.time_ns())


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog='live_view', description=__doc__.splitlines()[0])
    parser.add_argument('-p', '--port', type=int, default=DEFAULT_PORT,
                        help=f'the port (default {DEFAULT_PORT}; 0: any free one)')
    parser.add_argument('-b', '--bind', default='127.0.0.1',
                        help='the address to listen on (default 127.0.0.1: this machine only)')
    parser.add_argument('-t', '--topics', default='', help='serve topics matching this regex (default all)')
    parser.add_argument('-x', '--exclude', default=DEFAULT_EXCLUDE, help='leave out topics matching this regex')
    args = parser.parse_args(sys.argv[1:] if argv is None else argv[1:])
    context = foxglove.Context()
    sink = FoxgloveSink(context)
    try:
        server = foxglove.start_server(name='wurde live_view', host=args.bind, port=args.port,
                                       server_listener=sink, context=context)
    except RuntimeError as error:
        print(f'live_view: cannot serve on {args.bind}:{args.port}: {error}', file=sys.stderr, flush=True)
        return 1
    try:
        with tap_node('wurde_live_view') as (node, executor, stopped):
            tap = TopicTap(node, args.topics, args.exclude, sink.open_channel, sink.write, 'live_view')
            print(f'live_view ready on ws://{args.bind}:{server.port}', flush=True)

            def done() -> bool:
                sink.resend()
                return stopped()
            run_tap(tap, executor, done)
    finally:
        server.stop()
    print(f'live_view: {tap.count} messages on {len(sink.channels)} topics, {sink.subscriptions} '
          'subscriptions served', flush=True)
    return 0


if __name__ == '__main__':
    sys.exit(main())
