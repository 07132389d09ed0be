"""Benchmark: the VisionModule's operators in frames per second (WURDE guide 7.2.3), against raw
OpenCV and raw rclpy in the same run.

- ImageWriter (``.ppm``, the guide's: "about 25 fps ... at 320x240 color ppms") against a raw
  ``cv2.imwrite`` loop writing the same frames under the same names.
- ImagePublisher (format rgb: BGR->RGB, an ImageTransport event and a ``sensor_msgs/Image`` per
  frame) against a raw rclpy node publishing a ``sensor_msgs/Image`` (the same conversion) per
  frame; one raw rclpy subscriber process per run reads the ``sensor_msgs/Image`` topic and
  counts what it received.

At 320x240 and 640x480, colour, distinct frames cycled, offered as fast as the operator takes
them; the writers' figures are medians of three alternating rounds of ``--seconds`` / 3 each
(default 3 s in all), the publishers' one run of ``--seconds``. The operators
run in this process exactly as vision_module runs them (setup, then process per frame).

Usage: ``make bench-vision`` or ``python bench/vision.py`` inside ``source env.sh`` after a build.
ROS_DOMAIN_ID: the environment's if set (use 220-229 by hand), else one claimed like the tests'.
"""

from __future__ import annotations

import argparse
import array
import os
import pathlib
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from typing import Any

import cv2
import numpy as np

SIZES = ((320, 240), (640, 480))
FRAMES = 16


def frames(width: int, height: int) -> list[np.ndarray]:
    rng = np.random.default_rng(5)
    return [rng.integers(0, 256, (height, width, 3), dtype=np.uint8) for _ in range(FRAMES)]


class _Logger:
    def warn(self, text: str) -> None:
        print(text, file=sys.stderr)


def _spec(name: str, kind: str, options: dict[str, str]) -> Any:
    from wurde_drivers.vision.vision_config import OperatorSpec
    return OperatorSpec(name, kind, ('Bench',), options)


def _frame(images: list[np.ndarray], i: int) -> Any:
    from wurde_drivers.vision.camera import Frame
    return Frame('Bench', i, 1000.0 + i / 30, images[i % len(images)])


def _write_loop(write: Any, images: list[np.ndarray], seconds: float) -> float:
    count, start = 0, time.perf_counter()
    while time.perf_counter() - start < seconds:
        write(_frame(images, count))
        count += 1
    return count / (time.perf_counter() - start)


def bench_writer(images: list[np.ndarray], seconds: float, directory: str) -> tuple[float, float]:
    """(ImageWriter fps, raw cv2.imwrite fps): medians of three alternating rounds, each writing
    into a fresh directory that is removed afterwards (so neither side inherits the other's
    dirty pages or a directory of thousands of files)."""
    from wurde_drivers.vision.operator import OperatorContext
    from wurde_drivers.vision.operators.image_writer import ImageWriter
    from wurde_drivers.vision.playback import image_name
    ours: list[float] = []
    raw: list[float] = []
    for round_ in range(3):
        for side in (('raw', 'ours') if round_ % 2 else ('ours', 'raw')):
            target = tempfile.mkdtemp(dir=directory)
            if side == 'ours':
                writer = ImageWriter(_spec('BenchWriter', 'ImageWriter', {'imageDir': target}))
                writer.setup(OperatorContext(None, _Logger(), target))
                ours.append(_write_loop(lambda f: writer.process({'Bench': f}), images, seconds / 3))
                assert writer.failed == 0
            else:
                def write(frame: Any) -> None:
                    name = image_name('raw', frame.index, 'main', frame.stamp, '.ppm')
                    assert cv2.imwrite(os.path.join(target, name), frame.image)
                raw.append(_write_loop(write, images, seconds / 3))
            shutil.rmtree(target)
    return statistics.median(ours), statistics.median(raw)


def subscriber(topic: str) -> subprocess.Popen[str]:
    return subprocess.Popen([sys.executable, __file__, '--subscribe', topic], stdin=subprocess.PIPE,
                            stdout=subprocess.PIPE, text=True)


def _received(child: subprocess.Popen[str]) -> int:
    out, _ = child.communicate('stop\n', timeout=30)
    return int(out.split()[-1])


def _wait_matched(publisher: Any, spin: Any, timeout: float = 30.0) -> None:
    deadline = time.monotonic() + timeout
    while publisher.get_subscription_count() < 1:
        if time.monotonic() > deadline:
            raise SystemExit('no subscriber matched within 30 s')
        spin()


def bench_publisher(images: list[np.ndarray], seconds: float,
                    size: tuple[int, int]) -> dict[str, tuple[float, float]]:
    """{'ImagePublisher' | 'raw rclpy': (published fps, received fps)}."""
    from wurde_core import CommsManager
    from wurde_drivers.vision.operator import OperatorContext
    from wurde_drivers.vision.operators.image_publisher import ImagePublisher
    results = {}
    stream = f'BenchPub{size[0]}'
    child = subscriber(f'/{stream}/image_raw')
    manager = CommsManager(f'BenchVision{size[0]}')
    publisher = ImagePublisher(_spec(stream, 'ImagePublisher', {'format': 'rgb'}))
    publisher.setup(OperatorContext(manager, _Logger(), '.'))
    manager.step()
    _wait_matched(publisher._image_pub, manager.step)
    count, start = 0, time.perf_counter()
    while time.perf_counter() - start < seconds:
        publisher.process({'Bench': _frame(images, count)})
        count += 1
        if count % 10 == 0:
            manager.step()
    elapsed = time.perf_counter() - start
    results['ImagePublisher (rgb)'] = (count / elapsed, _received(child) / elapsed)
    manager.clean_up()
    results['raw rclpy Image (rgb8)'] = _raw_publisher(images, seconds, f'/Raw{size[0]}/image_raw')
    return results


def _raw_publisher(images: list[np.ndarray], seconds: float, topic: str) -> tuple[float, float]:
    import rclpy
    from rclpy.context import Context
    from rclpy.qos import QoSProfile, ReliabilityPolicy
    from sensor_msgs.msg import Image
    child = subscriber(topic)
    context = Context()
    rclpy.init(context=context)
    try:
        node = rclpy.create_node('raw_image_publisher', context=context)
        pub = node.create_publisher(Image, topic, QoSProfile(depth=5, reliability=ReliabilityPolicy.RELIABLE))
        _wait_matched(pub, lambda: time.sleep(0.01))
        count, start = 0, time.perf_counter()
        while time.perf_counter() - start < seconds:
            image = images[count % len(images)]
            rgb = cv2.cvtColor(image, cv2.COLOR_BGR2RGB)
            msg = Image()
            msg.header.stamp.sec = count
            msg.header.frame_id = 'Bench'
            msg.height, msg.width = image.shape[:2]
            msg.encoding, msg.step = 'rgb8', 3 * image.shape[1]
            msg.data = array.array('B', rgb.tobytes())
            pub.publish(msg)
            count += 1
        elapsed = time.perf_counter() - start
        return count / elapsed, _received(child) / elapsed
    finally:
        rclpy.shutdown(context=context)


def run_subscriber(topic: str) -> int:
    """Child: count ``sensor_msgs/Image`` messages on ``topic`` until stdin says stop."""
    import select

    import rclpy
    from rclpy.context import Context
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.qos import QoSProfile, ReliabilityPolicy
    from sensor_msgs.msg import Image
    context = Context()
    rclpy.init(context=context)
    node = rclpy.create_node('raw_image_counter', context=context)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    count = [0]
    node.create_subscription(Image, topic, lambda _: count.__setitem__(0, count[0] + 1),
                             QoSProfile(depth=5, reliability=ReliabilityPolicy.RELIABLE))
    while not select.select([sys.stdin], [], [], 0)[0]:
        executor.spin_once(timeout_sec=0.05)
    print(count[0], flush=True)
    rclpy.shutdown(context=context)
    return 0


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--seconds', type=float, default=3.0)
    parser.add_argument('--subscribe', help=argparse.SUPPRESS)
    args = parser.parse_args()
    os.environ['ROS_AUTOMATIC_DISCOVERY_RANGE'] = 'LOCALHOST'
    if args.subscribe:
        return run_subscriber(args.subscribe)
    claim = None
    if 'ROS_DOMAIN_ID' not in os.environ:
        from wurde_testing import claim_domain_id
        claim = claim_domain_id()
        os.environ['ROS_DOMAIN_ID'] = str(claim.domain_id)
    print(f'vision benchmark, ROS_DOMAIN_ID={os.environ["ROS_DOMAIN_ID"]}, {os.cpu_count()} cores, '
          f'{args.seconds:g} s per figure, OpenCV {cv2.__version__}')
    rows: list[tuple[str, str, float, float | None]] = []
    with tempfile.TemporaryDirectory(prefix='bench-vision-') as directory:
        for width, height in SIZES:
            images = frames(width, height)
            ours, raw = bench_writer(images, args.seconds, directory)
            rows.append((f'{width}x{height}', 'ImageWriter (.ppm)', ours, None))
            rows.append((f'{width}x{height}', 'raw cv2.imwrite (.ppm)', raw, None))
            for name, (sent, got) in bench_publisher(images, args.seconds, (width, height)).items():
                rows.append((f'{width}x{height}', name, sent, got))
    print(f'\n{"size":9} {"what":28} {"frames/s":>9} {"received/s":>11}')
    for size, name, rate, received in rows:
        print(f'{size:9} {name:28} {rate:9.1f} {"" if received is None else f"{received:11.1f}"}')
    if claim is not None:
        claim.release()
    return 0


if __name__ == '__main__':
    sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1] / 'src' / 'wurde_drivers'))
    sys.exit(main())
