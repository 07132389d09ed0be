"""live_view (wurde_mcp.recording.live_view) as a real process, read by a real WebSocket client
speaking Foxglove's WebSocket protocol (v1; the SDK's server names it ``foxglove.sdk.v1`` in the
handshake, the Foxglove app asks for it so): the channels are advertised with their
ros2msg definitions, a subscription gets the CDR bytes of the stream's messages (decoded here with
rclpy), a latched info published before anyone subscribed still arrives, and the server listens
on 127.0.0.1 only.

foxglove-sdk 0.30.3 sends a channel's advertisement before it enters the channel in the client's
table (``ConnectedClient::advertise_channels``): a subscription that comes back in between, which
a loaded machine makes possible, is refused with the status ``Unknown channel ID: N``. The client
here subscribes again then, as the manual (docs/ros2.md) tells a viewer to."""

from __future__ import annotations

import json
import re
import struct
import time
from typing import Any

from rclpy.serialization import deserialize_message
from websockets.exceptions import ConnectionClosed
from websockets.sync.client import connect
from wurde_core import CommsManager, Pose3D, topic
from wurde_core.interfaces import LocalizationPose
from wurde_mcp.recording import message_definition
from wurde_mcp.recording.tap import message_class
from wurde_testing import ChildProcess, find_executable
from wurde_testing.sockets import LOOPBACK, listening_addresses

STREAM = 'Localization/Live'
DEADLINE = 30.0
#: Foxglove WebSocket protocol v1: the SDK's subprotocol, and the binary opcode of a message for a
#: subscription (then the subscription id, u32, and the log time, u64, little-endian).
SUBPROTOCOL = 'foxglove.sdk.v1'
MESSAGE_DATA = 0x01
#: The SDK's refusal of a subscription to a channel not yet in the client's table.
UNKNOWN_CHANNEL = re.compile(r'Unknown channel ID: (\d+)')


def test_a_foxglove_client_sees_the_streams_as_ros_sends_them(ros_domain: int) -> None:
    manager = CommsManager('Viewed')
    manager.set_no_sleep()
    pose = LocalizationPose(STREAM)
    manager.register_supplier(pose)
    data_topic, info_topic = topic(STREAM, 'data'), topic(STREAM, 'info')
    try:
        pose.info.cmd_flags.set_value(7)
        pose.publish_info()                     # latched, before the viewer exists
        with ChildProcess([find_executable('wurde_mcp', 'live_view'), '-p', '0', '-t', '^/wurde/']) as view:
            ready = view.expect('live_view ready on', timeout=60)
            port = int(re.search(r'ws://127\.0\.0\.1:(\d+)', ready).group(1))
            assert listening_addresses(port) == [LOOPBACK], 'not 127.0.0.1 alone'
            with connect(f'ws://127.0.0.1:{port}', subprotocols=[SUBPROTOCOL],
                         open_timeout=DEADLINE) as client:
                channels: dict[str, dict[str, Any]] = {}
                deadline = time.monotonic() + DEADLINE * 2
                while not {data_topic, info_topic} <= set(channels):
                    assert time.monotonic() < deadline, f'advertised only {sorted(channels)}'
                    assert view.process.poll() is None, view.stderr
                    manager.step()
                    try:
                        frame = client.recv(timeout=0.2)
                    except TimeoutError:
                        continue
                    if isinstance(frame, str) and json.loads(frame)['op'] == 'advertise':
                        channels.update({c['topic']: c for c in json.loads(frame)['channels']})
                for name in (data_topic, info_topic):
                    advertised = channels[name]
                    assert (advertised['encoding'], advertised['schemaEncoding']) == ('cdr', 'ros2msg')
                    assert advertised['schema'] == message_definition(advertised['schemaName'])
                wanted = {1: channels[data_topic]['id'], 2: channels[info_topic]['id']}
                client.send(json.dumps({'op': 'subscribe', 'subscriptions': [
                    {'id': subscription, 'channelId': channel} for subscription, channel in wanted.items()]}))
                got: dict[int, Any] = {}
                sent = 0
                while len(got) < 2:
                    assert time.monotonic() < deadline, \
                        f'messages of subscriptions {sorted(got)} only\n{view.stdout}{view.stderr}'
                    sent += 1
                    pose.data.pose = Pose3D(float(sent), 0.5, 0.0, 0.1, 0.0, 0.0)
                    pose.publish_data()
                    manager.step()
                    try:
                        frame = client.recv(timeout=0.2)
                    except TimeoutError:
                        continue
                    refused = UNKNOWN_CHANNEL.search(frame) if isinstance(frame, str) else None
                    if refused:
                        client.send(json.dumps({'op': 'subscribe', 'subscriptions': [
                            {'id': subscription, 'channelId': channel} for subscription, channel in wanted.items()
                            if channel == int(refused.group(1))]}))
                    if isinstance(frame, bytes) and frame[0] == MESSAGE_DATA:
                        subscription, _stamp = struct.unpack_from('<IQ', frame, 1)
                        name = data_topic if subscription == 1 else info_topic
                        got[subscription] = deserialize_message(
                            frame[13:], message_class(channels[name]['schemaName']))
            assert 1 <= got[1].pose.x <= sent and got[1].pose.y == 0.5
            assert got[2].cmd_flags == 7
            view.process.send_signal(2)
            assert view.process.wait(timeout=DEADLINE) == 0, view.stderr
    except ConnectionClosed as closed:
        raise AssertionError(f'the server closed the connection: {closed}') from closed
    finally:
        manager.clean_up()
