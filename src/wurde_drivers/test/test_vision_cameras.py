"""Cameras without ROS: the playback camera's naming, order and corrupt-file skipping, and an
OpenCV capture device (a real video file written by cv2.VideoWriter) that vanishes and comes back.

Every wait polls the camera against a deadline (the retry period is one second)."""

from __future__ import annotations

import os
import pathlib
import time
from collections.abc import Callable

import cv2
import numpy as np
import pytest

from wurde_drivers.vision.camera import RETRY_S, Camera, Frame
from wurde_drivers.vision.camera_config import CameraSpec
from wurde_drivers.vision.capture import CaptureCamera
from wurde_drivers.vision.playback import PlaybackCamera, image_name, image_pattern, list_images


def spec(kind: str, **options: str) -> CameraSpec:
    return CameraSpec('cam', kind, options, path='', line=1)


def read_until(camera: Camera, done: Callable[[list[Frame]], bool], what: str,
               timeout: float = 10.0) -> list[Frame]:
    frames: list[Frame] = []
    deadline = time.monotonic() + timeout
    while not done(frames):
        assert time.monotonic() < deadline, f'{what}: not within {timeout} s ({len(frames)} frames)'
        frame = camera.read()
        if frame is not None:
            frames.append(frame)
        else:
            time.sleep(0.005)   # polling interval, not a wait for anything
    return frames


def image(i: int, shape: tuple[int, int] = (48, 64)) -> np.ndarray:
    rng = np.random.default_rng(i)
    return rng.integers(0, 256, (*shape, 3), dtype=np.uint8)


def test_guide_file_names() -> None:
    assert image_name('faceTest', 12, 'main', 1234.5, '.ppm') == 'faceTest-12-main-1234.500000.ppm'
    assert image_name('', 3, '', 2.0, '.png') == '3-2.000000.png'
    pattern = image_pattern('faceTest', 'main', '.ppm')
    assert pattern.match('faceTest-12-main-1234.5.ppm').groups() == ('12', '1234.5')
    for other in ('faceTest-12-stereo-1234.5.ppm', 'faceTest-x-main-1.ppm', 'faceTest-12-main-1.pgm',
                  'other-12-main-1.ppm'):
        assert pattern.match(other) is None, other


def test_playback_plays_in_frame_order_skips_corrupt_files_and_ends(tmp_path: pathlib.Path) -> None:
    frames_in = {i: image(i) for i in range(12)}
    for i, pixels in frames_in.items():
        assert cv2.imwrite(str(tmp_path / image_name('set', i, 'main', 100.0 + i / 10, '.ppm')), pixels)
    # Neither of these is part of the set; the corrupt one is, and is skipped.
    cv2.imwrite(str(tmp_path / image_name('set', 99, 'stereo', 1.0, '.ppm')), image(99))
    (tmp_path / 'notes.txt').write_text('not an image')
    (tmp_path / image_name('set', 5, 'main', 100.5, '.ppm')).write_bytes(b'P6\n64 48\n255\ngarbage')
    assert [i for i, _, _ in list_images(str(tmp_path), 'set', 'main', '.ppm')] == list(range(12))
    reports: list[str] = []
    camera = PlaybackCamera(spec('playback', imageDirectory=str(tmp_path), imagePrefix='set',
                                 imageDevice='main', imageSuffix='.ppm', frameRate='0', loop='false'),
                            reports.append)
    frames = read_until(camera, lambda _: camera.finished, 'the whole set')
    assert [f.index for f in frames] == [i for i in range(12) if i != 5]    # 10 after 9, not after 1
    for frame in frames:
        assert np.array_equal(frame.image, frames_in[frame.index])
        assert frame.stamp == pytest.approx(100.0 + frame.index / 10)
    assert camera.skipped == 1 and any('skipped' in r and 'set-5-main' in r for r in reports)
    assert camera.read() is None and camera.frames == 11


def test_playback_every_opencv_type_and_loop(tmp_path: pathlib.Path) -> None:
    for i in range(3):
        cv2.imwrite(str(tmp_path / image_name('p', i, '', float(i + 1), '.png')), image(i))
    camera = PlaybackCamera(spec('playback', imageDirectory=str(tmp_path), imagePrefix='p',
                                 imageDevice='', imageSuffix='.png', frameRate='0', loop='true'))
    frames = read_until(camera, lambda f: len(f) >= 7, 'looping')
    assert [f.index for f in frames] == [0, 1, 2, 0, 1, 2, 0]
    assert np.array_equal(frames[4].image, image(1))


def test_playback_directory_absent_then_present(tmp_path: pathlib.Path) -> None:
    directory = tmp_path / 'later'
    reports: list[str] = []
    camera = PlaybackCamera(spec('playback', imageDirectory=str(directory), imagePrefix='',
                                 imageDevice='main', imageSuffix='.ppm', frameRate='0', loop='false'),
                            reports.append)
    assert camera.read() is None and camera.outages == 1 and 'absent' in reports[0]
    directory.mkdir()
    cv2.imwrite(str(directory / image_name('', 7, 'main', 5.0, '.ppm')), image(7))
    frames = read_until(camera, lambda f: len(f) == 1, 'the image after the retry', timeout=RETRY_S + 5)
    assert frames[0].index == 7 and camera.outages == 1


def write_video(path: pathlib.Path, count: int) -> list[np.ndarray]:
    """A real MJPG video; the frames as OpenCV reads them back (MJPG is lossy)."""
    writer = cv2.VideoWriter(str(path), cv2.VideoWriter_fourcc(*'MJPG'), 30, (64, 48))
    assert writer.isOpened()
    for i in range(count):
        writer.write(np.full((48, 64, 3), 30 * i, np.uint8))
    writer.release()
    capture = cv2.VideoCapture(str(path))
    frames = [capture.read()[1] for _ in range(count)]
    capture.release()
    return frames


def test_capture_device_vanishes_and_comes_back(tmp_path: pathlib.Path) -> None:
    video = tmp_path / 'camera.avi'
    expected = write_video(video, 4)
    kept = video.read_bytes()
    reports: list[str] = []
    camera = CaptureCamera(spec('firewire', id=str(video), shutter='2048', autoiris='true',
                                brightness='128', frameRate='0'), reports.append)
    # Options OpenCV has no property for are reported by name.
    assert any('option shutter has no OpenCV' in r for r in reports)
    assert any('option autoiris has no OpenCV' in r for r in reports)
    frames = read_until(camera, lambda f: len(f) == 4, 'the four frames')
    assert all(np.array_equal(f.image, e) for f, e in zip(frames, expected))
    assert [f.index for f in frames] == [0, 1, 2, 3]
    os.unlink(video)            # unplugged: the end of its frames, then it cannot be opened
    deadline = time.monotonic() + RETRY_S + 10
    while camera.open_failures == 0:     # noticed, closed, and tried again while it is away
        assert time.monotonic() < deadline, f'vanishing not noticed: {reports}'
        assert camera.read() is None
        time.sleep(0.005)
    assert camera.outages == 1 and not camera.up
    assert sum('vanished' in r for r in reports) == 1     # one report per outage, not per retry
    video.write_bytes(kept)     # plugged in again
    frames = read_until(camera, lambda f: len(f) == 4, 'frames after the device came back',
                        timeout=RETRY_S + 10)
    assert all(np.array_equal(f.image, e) for f, e in zip(frames, expected))
    assert frames[0].index == 4          # the camera's count goes on
    assert 'is back' in reports[-1]
    camera.close()
    camera.close()                       # idempotent


def test_capture_ids_that_name_no_device() -> None:
    reports: list[str] = []
    camera = CaptureCamera(spec('firewire', id='0x8004602000301fc'), reports.append)  # the guide's 1394 id
    assert camera.read() is None and not camera.up and camera.outages == 1
    assert 'names no capture device' in reports[0]
    missing = CaptureCamera(spec('firewire', id='/nonexistent/video0'), reports.append)
    assert missing.read() is None and 'no such device' in reports[-1]


def test_a_camera_with_nothing_ready_does_not_ask_for_a_busy_loop(tmp_path: pathlib.Path) -> None:
    cv2.imwrite(str(tmp_path / image_name('', 0, '', 1.0, '.ppm')), image(0))
    camera = PlaybackCamera(spec('playback', imageDirectory=str(tmp_path), imagePrefix='',
                                 imageDevice='', imageSuffix='.ppm', frameRate='50', loop='false'))
    read_until(camera, lambda f: len(f) == 1, 'the one frame')
    assert 0.0 < camera.wait_s() <= 0.02                    # paced: the next frame's time
    read_until(camera, lambda _: camera.finished, 'the end')
    assert camera.wait_s() == float('inf')                   # finished: the loop's own sleep
