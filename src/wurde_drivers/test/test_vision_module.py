"""vision_module end to end (guide 7.2): a real process with a playback camera of real image
files, an ImagePublisher and an ImageWriter; a wurde_core consumer in the test receives the
exact frames on ImageTransport and on ``sensor_msgs/Image``, the writer's files hold them, and
VisionControl reports, stops an operator, sets an option and reloads the file. A bad config
ends the program with file:line."""

from __future__ import annotations

import pathlib
import subprocess
from collections.abc import Iterator

import cv2
import numpy as np
import pytest
import rclpy
from rclpy.context import Context
from rclpy.executors import SingleThreadedExecutor
from sensor_msgs.msg import Image
from sim_fixture import Observer
from wurde_testing import ChildProcess, find_executable

from wurde_drivers.vision.playback import image_name

WIDTH, HEIGHT, FRAMES = 352, 288, 6      # CIF: not the guide's 320x240


def images(directory: pathlib.Path) -> dict[int, np.ndarray]:
    """FRAMES distinct PNG images named as the guide says, and one corrupt file among them."""
    directory.mkdir()
    rng = np.random.default_rng(3)
    made = {}
    for index in range(FRAMES):
        made[index] = rng.integers(0, 256, (HEIGHT, WIDTH, 3), dtype=np.uint8)
        assert cv2.imwrite(str(directory / image_name('set', index, 'main', 50.0 + index, '.png')),
                           made[index])
    (directory / image_name('set', FRAMES, 'main', 50.0 + FRAMES, '.png')).write_bytes(b'\x89PNG broken')
    return made


def configs(tmp_path: pathlib.Path, out: pathlib.Path) -> tuple[pathlib.Path, pathlib.Path]:
    camera = tmp_path / 'camera-config.xml'
    camera.write_text("""<?xml version="1.0"?>
<camera-config>
  <camera name="Play" type="playback">
    <option name="imageDirectory" value="images"/>
    <option name="imagePrefix" value="set"/>
    <option name="imageDevice" value="main"/>
    <option name="imageSuffix" value=".png"/>
    <option name="frameRate" value="15"/>
    <option name="loop" value="true"/>
  </camera>
</camera-config>
""")
    vision = tmp_path / 'vision-config.xml'
    vision.write_text(f"""<?xml version="1.0"?>
<vision-config>
  <module name="Vis">
    <camera name="Play"/>
    <operator name="Pub" type="ImagePublisher" camera="Play">
      <option name="format" value="rgb"/>
    </operator>
    <operator name="Writer" type="ImageWriter">
      <camera name="Play"/>
      <option name="imageDir" value="{out}"/>
      <option name="imagePrefix" value="copy"/>
    </operator>
  </module>
</vision-config>
""")
    return camera, vision


class StandardImages:
    """A plain rclpy subscriber to a ``sensor_msgs/Image`` topic, in a context of its own."""

    def __init__(self, topic: str) -> None:
        self.context = Context()
        rclpy.init(context=self.context)
        self.node = rclpy.create_node('image_reader', context=self.context)
        self.executor = SingleThreadedExecutor(context=self.context)
        self.executor.add_node(self.node)
        self.messages: list[Image] = []
        self.node.create_subscription(Image, topic, self.messages.append, 5)

    def spin(self) -> list[Image]:
        """Take in what arrived (no waiting) and return every message so far."""
        for _ in range(5):
            self.executor.spin_once(timeout_sec=0.0)
        return self.messages

    def close(self) -> None:
        rclpy.shutdown(context=self.context)


@pytest.fixture
def observer(ros_domain: int) -> Iterator[Observer]:
    watcher = Observer({'Pub': 'ImageTransport', 'VisControl': 'VisionControl'})
    try:
        yield watcher
    finally:
        watcher.close()


def test_playback_frames_reach_consumers_and_disk_exactly(observer: Observer, tmp_path: pathlib.Path) -> None:
    made = images(tmp_path / 'images')
    out = tmp_path / 'out'
    camera, vision = configs(tmp_path, out)
    images_std = StandardImages('/Pub/image_raw')
    standard = images_std.messages
    program = find_executable('wurde_drivers', 'vision_module')
    with ChildProcess([program, '-c', str(camera), '-v', str(vision), '-n', 'Vis']) as child:
        def seen(o: Observer) -> set[int]:
            return {m.frame_index for _, m in o.events['Pub']}
        try:
            observer.until(lambda o: seen(o) == set(made) and 'Pub' in o.infos
                           and len({m.header.stamp.sec for m in images_std.spin()}) >= 3,
                           'every frame on ImageTransport and three on image_raw')
        finally:
            images_std.close()
        for _, message in observer.events['Pub']:
            assert (message.width, message.height, message.encoding, message.step) == \
                (WIDTH, HEIGHT, 'rgb8', 3 * WIDTH)
            rgb = cv2.cvtColor(made[message.frame_index], cv2.COLOR_BGR2RGB)
            assert bytes(message.data) == rgb.tobytes(), f'frame {message.frame_index} differs'
            assert message.header.stamp.sec == 50 + message.frame_index       # the logged time
        for message in standard:
            index = message.header.stamp.sec - 50
            assert (message.encoding, message.header.frame_id, message.width) == ('rgb8', 'Play', WIDTH)
            assert bytes(message.data) == cv2.cvtColor(made[index], cv2.COLOR_BGR2RGB).tobytes()
        info = observer.infos['Pub']
        assert (info.camera, info.format, info.width, info.height) == ('Play', 'rgb', WIDTH, HEIGHT)
        # The writer's files: the frames, named as the playback camera reads them (the writer
        # runs after the publisher in a turn, so its last file may still be on its way).
        paths = {index: out / image_name('copy', index, 'main', 50.0 + index, '.ppm') for index in made}
        observer.until(lambda _: all(path.exists() for path in paths.values()), 'the written frames')
        for index, pixels in made.items():
            path = paths[index]
            written = cv2.imread(str(path))
            assert written is not None and np.array_equal(written, pixels), path
        # VisionControl: the layout, and a stop command.
        # The status comes once a second: wait for one sent after every frame was taken.
        observer.until(lambda o: bool(o.events['VisControl'])
                       and o.events['VisControl'][-1][1].frame_count >= FRAMES, 'VisionControl status')
        status = observer.events['VisControl'][-1][1]
        assert (status.layout, list(status.cameras), list(status.camera_types)) == \
            ('Vis', ['Play'], ['playback'])
        assert list(status.operator_names) == ['Pub', 'Writer']
        assert list(status.operator_types) == ['ImagePublisher', 'ImageWriter']
        assert list(status.operator_running) == [True, True]
        observer.request('VisControl', command=2, operator_name='Writer')
        observer.until(lambda o: list(o.events['VisControl'][-1][1].operator_running) == [True, False],
                       'Writer stopped')
        # Set option: the publisher turns to gray; the info says so and the pixels follow.
        observer.request('VisControl', command=3, operator_name='Pub', option_name='format',
                         option_value='gray')
        observer.until(lambda o: o.events['Pub'][-1][1].encoding == 'mono8'
                       and o.infos['Pub'].format == 'gray', 'gray frames')
        gray = observer.events['Pub'][-1][1]
        assert bytes(gray.data) == cv2.cvtColor(made[gray.frame_index], cv2.COLOR_BGR2GRAY).tobytes()
        # Reload: the file now says yuv422; the running publisher takes it.
        vision.write_text(vision.read_text().replace('value="rgb"', 'value="yuv422"'))
        observer.request('VisControl', command=4)
        observer.until(lambda o: o.events['Pub'][-1][1].encoding == 'yuv422', 'yuv422 frames after reload')
        uyvy = observer.events['Pub'][-1][1]
        assert bytes(uyvy.data) == cv2.cvtColor(made[uyvy.frame_index], cv2.COLOR_BGR2YUV_UYVY).tobytes()
        assert child.stop() == 0
    assert 'skipped' in child.stderr and f'set-{FRAMES}-main' in child.stderr   # the corrupt file


def test_bad_config_exits_with_file_and_line(ros_domain: int, tmp_path: pathlib.Path) -> None:
    camera = tmp_path / 'camera-config.xml'
    camera.write_text('<?xml version="1.0"?>\n<camera-config>\n<camera name="c" type="firewire"/>\n'
                      '</camera-config>\n')
    vision = pathlib.Path(__file__).resolve().parents[3] / 'config' / 'vision' / 'vision-config.xml'
    program = find_executable('wurde_drivers', 'vision_module')
    result = subprocess.run([program, '-c', str(camera), '-v', str(vision), '-n', 'LeftVisionModule'],
                            capture_output=True, text=True, timeout=60, check=False)
    assert result.returncode == 2
    assert f'{camera}:3: camera "c" needs option(s) id' in result.stderr


def test_stereo_data_collector_logs_matching_sets(observer: Observer, tmp_path: pathlib.Path) -> None:
    """Two cameras, a RangeFinder and an Egomotion supplied from the test: each set of files
    shares one frame index and keeps each source's timestamp (guide 7.2.3's naming)."""
    from wurde_core import Pose, Time
    from wurde_core.interfaces import Egomotion, RangeFinder

    made = images(tmp_path / 'images')
    for index, pixels in made.items():       # the same scenes as the stereo camera's, mirrored
        cv2.imwrite(str(tmp_path / 'images' / image_name('set', index, 'stereo', 80.0 + index, '.png')),
                    pixels[:, ::-1])
    out = tmp_path / 'out'
    camera = tmp_path / 'camera-config.xml'
    camera.write_text('<?xml version="1.0"?>\n<camera-config>\n' + ''.join(
        f'<camera name="{name}" type="playback"><option name="imageDirectory" value="images"/>'
        f'<option name="imagePrefix" value="set"/><option name="imageDevice" value="{device}"/>'
        '<option name="imageSuffix" value=".png"/><option name="frameRate" value="10"/>'
        '<option name="loop" value="true"/></camera>\n'
        for name, device in (('Left', 'main'), ('Right', 'stereo'))) + '</camera-config>\n')
    vision = tmp_path / 'vision-config.xml'
    vision.write_text(f"""<?xml version="1.0"?>
<vision-config><module name="Collect"><camera name="Left"/><camera name="Right"/>
  <operator name="Stereo" type="StereoDataCollector">
    <camera name="Left"/><camera name="Right"/>
    <option name="imageDir" value="{out}"/><option name="imagePrefix" value="run"/>
    <option name="laser" value="TestLaser"/><option name="odometry" value="TestOdo"/>
  </operator>
</module></vision-config>
""")
    laser, odometry = RangeFinder('TestLaser'), Egomotion('TestOdo')
    for stream in (laser, odometry):
        stream.set_auto_timestamp(False)
        observer.manager.register_supplier(stream)
    laser.data.ranges = [1.5, 2.25, 8.0]
    laser.data.timestamp = Time(77.5)
    odometry.data.location = Pose(1.0, -2.0, 0.5)
    odometry.data.tv, odometry.data.rv = 0.25, -0.125
    odometry.data.timestamp = Time(78.25)

    def complete_sets() -> list[int]:
        """Set indices with main, stereo, laser and odometry files (the odometry is written last)."""
        indices = [int(path.name.split('-')[1]) for path in out.glob('run-*-odometry-*.txt')]
        return sorted(i for i in indices if all(any(out.glob(f'run-{i}-{device}-*'))
                                                for device in ('main', 'stereo', 'laser')))

    def feed_and_check(_: Observer) -> bool:
        laser.publish_data()
        odometry.publish_data()
        return bool(complete_sets())

    program = find_executable('wurde_drivers', 'vision_module')
    with ChildProcess([program, '-c', str(camera), '-v', str(vision), '-n', 'Collect']) as child:
        observer.until(feed_and_check, 'a set with laser and odometry')
        assert child.stop() == 0
    index = complete_sets()[0]
    assert (out / f'run-{index}-laser-77.500000.txt').read_text() == '1.5 2.25 8.0\n'
    assert (out / f'run-{index}-odometry-78.250000.txt').read_text() == '1.0 -2.0 0.5 0.25 -0.125\n'
    main = sorted(out.glob(f'run-{index}-main-*.ppm'))
    stereo = sorted(out.glob(f'run-{index}-stereo-*.ppm'))
    assert len(main) == len(stereo) == 1
    def scene(path: pathlib.Path, first_stamp: float) -> int:
        """The scene a file shows, from its own stamp (the playback file's)."""
        return round(float(path.name.split('-')[3][:-4]) - first_stamp)

    assert np.array_equal(cv2.imread(str(main[0])), made[scene(main[0], 50.0)])
    assert np.array_equal(cv2.imread(str(stereo[0]))[:, ::-1], made[scene(stereo[0], 80.0)])
