"""The fuzz targets (issue 16): every codec, every XML reader, carmen.ini and the xmlServer's line
parser, each a function of one input's bytes.

A target either returns or raises one of its *documented* error types (the ``allowed`` tuple); any
other exception is a bug.  Codec stream deframers take any bytes and raise nothing at all (bad
frames are dropped and counted); single-frame decoders raise :class:`CodecError`; readers of files
a user writes raise :class:`ConfigError` (file, line, reason); the xmlServer's parser raises
:class:`CommandError` / :class:`VarError`.  Readers take a path, so their input is written to one
scratch file first.

Used by ``fuzz/run.py`` (atheris campaigns, ``make fuzz``) and by the corpus replay test that
``make test`` runs (``wurde_mcp/test/test_fuzz_corpus.py``).  Imports are inside the targets so a
campaign instruments only what its target reaches.
"""

from __future__ import annotations

import dataclasses
import os
import pathlib
import struct
import tempfile
from collections.abc import Callable

ROOT = pathlib.Path(__file__).resolve().parents[1]
CORPUS = ROOT / 'fuzz' / 'corpus'


@dataclasses.dataclass(frozen=True)
class Target:
    """One fuzz target: ``run(data)`` may raise only ``allowed()``'s types."""

    name: str
    run: Callable[[bytes], None]
    allowed: Callable[[], tuple[type[BaseException], ...]]
    #: shipped files whose bytes seed the corpus (globs from the repository root)
    seeds: tuple[str, ...] = ()


def _codec_error() -> tuple[type[BaseException], ...]:
    from wurde_drivers.errors import CodecError
    return (CodecError,)


def _config_error() -> tuple[type[BaseException], ...]:
    from wurde_idl.errors import ConfigError
    return (ConfigError,)


def _nothing() -> tuple[type[BaseException], ...]:
    return ()


def _command_error() -> tuple[type[BaseException], ...]:
    from wurde_mcp.xml_server.command import CommandError
    from wurde_mcp.xml_server.variables import VarError
    return (CommandError, VarError)


_SCRATCH: dict[str, pathlib.Path] = {}


def scratch(data: bytes, suffix: str = '.xml') -> str:
    """``data`` written to this process's scratch file (one per suffix, rewritten each time)."""
    path = _SCRATCH.get(suffix)
    if path is None:
        handle, name = tempfile.mkstemp(prefix='wurde-fuzz-', suffix=suffix)
        os.close(handle)
        path = _SCRATCH[suffix] = pathlib.Path(name)
    path.write_bytes(data)
    return str(path)


# -- codecs: stream deframers (nothing may escape) and frame decoders (CodecError only) ----------
def sick_stream(data: bytes) -> None:
    from wurde_drivers.sick import codec
    deframer = codec.Deframer()
    for telegram in deframer.feed(data[: len(data) // 2]) + deframer.feed(data[len(data) // 2:]):
        assert isinstance(telegram, codec.Telegram)


def sick_bodies(data: bytes) -> None:
    from wurde_drivers.sick import codec
    if not data:
        return
    body = data[1:]
    decoder = {0: codec.decode_b0, 1: codec.decode_bb, 2: codec.decode_f4,
               3: codec.decode_mode_reply}.get(data[0] % 5, codec.decode_telegram)
    decoder(body)


def rflex_stream(data: bytes) -> None:
    from wurde_drivers.rflex import codec
    for packet in codec.Deframer().feed(data):
        assert isinstance(packet, codec.Packet)


def rflex_frame(data: bytes) -> None:
    from wurde_drivers.rflex import codec
    codec.decode(data)


def ptu_stream(data: bytes) -> None:
    from wurde_drivers.ptu import codec
    codec.PtuDeframer().feed(data)


def ptu_commands(data: bytes) -> None:
    from wurde_drivers.ptu import codec
    tokens, _rest = codec.decode_commands(data)
    for token in tokens:
        try:
            codec.decode_command(token)
        except _codec_error():
            pass
    codec.decode_reply(data)


def wrist_frames(data: bytes) -> None:
    from wurde_drivers.wrist import codec
    if len(data) < 5:
        return
    (can_id,) = struct.unpack_from('<I', data)
    frame = (can_id, data[5:13], bool(data[4] & 1))
    (codec.decode_reply if data[4] & 2 else codec.decode_command)(frame)


def dmu_stream(data: bytes) -> None:
    from wurde_drivers.dmu import codec
    mode = codec.DmuMode.ANGLE if data[:1] == b'a' else codec.DmuMode.SCALED
    codec.DmuDeframer(mode).feed(data[1:])


def joystick_stream(data: bytes) -> None:
    from wurde_drivers.joystick import codec
    decoder = codec.JsDecoder()
    decoder.feed(data[: len(data) // 3])
    decoder.feed(data[len(data) // 3:])


def nmea_stream(data: bytes) -> None:
    from wurde_drivers.gps import codec
    codec.NmeaDeframer().feed(data)


def nmea_sentence(data: bytes) -> None:
    from wurde_drivers.gps import codec
    codec.decode(data)


# -- readers of files a user writes (ConfigError with file, line and reason) ---------------------
def interface_xml(data: bytes) -> None:
    from wurde_idl.reader import read_interface
    read_interface(scratch(data))


def mcp_config(data: bytes) -> None:
    from wurde_mcp.config import read_mcp_config
    read_mcp_config(scratch(data))


def mcp_mappings(data: bytes) -> None:
    from wurde_mcp.config import read_mcp_config, read_mcp_mappings
    read_mcp_mappings(scratch(data), read_mcp_config(ROOT / 'config' / 'sim' / 'mcp-config.xml'))


def _device_config(loader: str) -> Callable[[bytes], None]:
    def run(data: bytes) -> None:
        module, _, function = loader.rpartition('.')
        getattr(__import__(module, fromlist=[function]), function)(scratch(data))
    run.__name__ = loader.rpartition('.')[2]
    return run


def map_file(data: bytes) -> None:
    from wurde_idl.mapfile import load_map_data
    load_map_data(scratch(data))


def carmen_ini(data: bytes) -> None:
    from wurde_mcp.carmen.ini import read_ini
    read_ini(scratch(data, '.ini'))


def xml_server_line(data: bytes) -> None:
    from wurde_mcp.xml_server.command import parse_command
    from wurde_mcp.xml_server.variables import parse_value
    line = data.decode('utf-8', 'replace')
    parse_command(line)
    for typ in ('s', 'd', 'i', 'b'):
        try:
            parse_value(typ, line)
        except _command_error()[1]:
            pass


def _targets() -> dict[str, Target]:
    drivers = 'wurde_drivers.{0}.config.load_{0}_config'
    targets = [
        Target('sick_stream', sick_stream, _nothing),
        Target('sick_bodies', sick_bodies, _codec_error),
        Target('rflex_stream', rflex_stream, _nothing),
        Target('rflex_frame', rflex_frame, _codec_error),
        Target('ptu_stream', ptu_stream, _nothing),
        Target('ptu_commands', ptu_commands, _codec_error),
        Target('wrist_frames', wrist_frames, _codec_error),
        Target('dmu_stream', dmu_stream, _nothing),
        Target('nmea_stream', nmea_stream, _nothing),
        Target('nmea_sentence', nmea_sentence, _codec_error),
        Target('interface_xml', interface_xml, _config_error,
               ('src/wurde_interfaces/interfaces/*.xml',)),
        Target('mcp_config', mcp_config, _config_error,
               ('config/*/mcp-config.xml',)),
        Target('mcp_mappings', mcp_mappings, _config_error, ('config/*/mcp-mappings.xml',)),
        Target('laser_config', _device_config('wurde_drivers.sick.config.load_laser_config'),
               _config_error, ('config/sick/laser-config.xml',)),
        Target('map_file', map_file, _config_error, ('config/maps/*.xml',)),
        Target('sim_config', _device_config('wurde_drivers.sim.config.load_sim_config'),
               _config_error, ('config/*/sim-config.xml',)),
        Target('carmen_ini', carmen_ini, _config_error, ('config/carmen/*.ini',)),
        Target('xml_server_line', xml_server_line, _command_error),
        Target('joystick_stream', joystick_stream, _nothing),
        Target('joystick_config', _device_config('wurde_drivers.joystick.config.load_joystick_config'),
               _config_error, ('config/*/joystick-config.xml',)),
        Target('camera_config', _device_config('wurde_drivers.vision.camera_config.load_camera_config'),
               _config_error, ('config/vision/*camera-config.xml',)),
        Target('vision_config', _device_config('wurde_drivers.vision.vision_config.load_vision_config'),
               _config_error, ('config/vision/*vision-config.xml',)),
    ]
    for device in ('rflex', 'ptu', 'wrist', 'dmu', 'gps'):
        targets.append(Target(f'{device}_config', _device_config(drivers.format(device)),
                              _config_error, (f'config/{device}/{device}-config.xml',)))
    return {target.name: target for target in targets}


TARGETS = _targets()


def codec_seeds() -> dict[str, list[bytes]]:
    """Valid inputs for the codec targets, from the codecs' own encoders and the devices'
    documented examples (the corpus's starting points; the readers' seeds are shipped files)."""
    from wurde_drivers.joystick import codec as joystick
    from wurde_drivers.rflex import codec as rflex
    from wurde_drivers.sick import codec as sick
    from wurde_drivers.wrist import codec as wrist
    scan = sick.encode_b0([100, 200, 8191], 'mm')
    frames = wrist.encode_move(1, 0.5, 0.2, 0.4)
    return {
        'sick_stream': [sick.reply(0xB0, scan) + bytes([sick.ACK]) + sick.reply(0xA0, b'\x00')],
        'sick_bodies': [bytes([0]) + scan, bytes([3, 0])],
        'rflex_stream': [rflex.encode(rflex.set_dir(0, 100, 10, 0, 1)) + rflex.encode(rflex.sys_status_poll())],
        'rflex_frame': [rflex.encode(rflex.brake_release())],
        'ptu_stream': [b'* PP 100\r\n! Maximum allowable Pan position is 3090\r\n!T!T!P!P*\r\n!P\r\n'],
        'ptu_commands': [b'PP100 TP-50 PS1000 ', b'* 100\r\n'],
        'wrist_frames': [struct.pack('<I', f.arbitration_id) + b'\x00' + f.data for f in frames],
        'dmu_stream': [b'c\xff' + bytes(17), b'a\xff' + bytes(21)],
        'nmea_stream': [b'$GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,*47\r\n'],
        'nmea_sentence': [b'$GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,*47\r\n'],
        'joystick_stream': [joystick.encode_event(joystick.JsEvent(joystick.JS_EVENT_AXIS, 1, 0, 1000, init=True))
                            + joystick.encode_event(joystick.JsEvent(joystick.JS_EVENT_BUTTON, 3, 1, 1010))],
        'xml_server_line': [b'<var name="odoPose.pose"/>', b'<push t="0.5" cmd="var odoPose.pose"/>',
                            b'var drive.command="1 2 3"', b'help'],
    }


def corpus(target: Target) -> list[pathlib.Path]:
    """The kept inputs of ``target``: its corpus folder (seeds, coverage finds, crash repros)."""
    folder = CORPUS / target.name
    return sorted(path for path in folder.iterdir() if path.is_file()) if folder.is_dir() else []


def check(target: Target, data: bytes) -> None:
    """Run ``target`` on ``data``; a documented error is a clean refusal, anything else raises."""
    try:
        target.run(data)
    except target.allowed() as error:
        if isinstance(error, _config_error()):
            assert error.path and error.reason, f'{target.name}: a refusal without file or reason: {error!r}'
