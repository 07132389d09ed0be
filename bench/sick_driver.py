"""Benchmark: the SICK device layer at 500 kbaud with 361 values, against a raw pyserial loop.

The emulator (``SickEmulator``, paced like a real LMS: 37.5 scans/s at 0.5°) runs in this process on
a pty.  Each reader runs in a process of its own, so ``time.process_time`` there is its CPU alone:

1. ``driver``  ``SickLaser.connect()`` from 9600 to 500000 baud, then ``poll`` for N seconds;
2. ``raw``     a pyserial loop on the same pty at 500000 baud that only counts bytes (the floor:
               what reading the bytes costs before any deframing, CRC or decoding).

The table shows scans/s received against the emulator's scans/s sent in the same window (goal: the
driver keeps up, nothing lost) and CPU milliseconds per scan.  Nothing here touches ROS or DDS.

Usage: ``tools/in_env.sh python bench/sick_driver.py [--seconds 10]``.
"""

from __future__ import annotations

import argparse
import json
import pathlib
import subprocess
import sys
import time

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / 'src' / 'wurde_drivers'))   # measure the source tree

BAUD = 500000
VALUES = 361
TELEGRAM = 6 + 4 + 2 * VALUES      # bytes of one B0 telegram with 361 values


def run_driver(path: str, seconds: float) -> dict:
    from wurde_drivers.sick.device import SickLaser
    laser = SickLaser(path, baudrate=BAUD, resolution=0.5)
    laser.connect()
    print('START', flush=True)
    scans = 0
    cpu0, start = time.process_time(), time.monotonic()
    while time.monotonic() - start < seconds:
        scans += len(laser.poll(0.2))
    elapsed, cpu = time.monotonic() - start, time.process_time() - cpu0
    print('STOP', flush=True)
    stats = laser.stats
    laser.close()
    return {'scans': scans, 'elapsed': elapsed, 'cpu': cpu, 'bad_crc': stats.bad_crc,
            'skipped': stats.bytes_skipped}


def run_raw(path: str, seconds: float) -> dict:
    import serial
    port = serial.Serial(path, BAUD, timeout=0.2)
    port.reset_input_buffer()
    print('START', flush=True)
    received = 0
    cpu0, start = time.process_time(), time.monotonic()
    while time.monotonic() - start < seconds:
        received += len(port.read(port.in_waiting or 1))
    elapsed, cpu = time.monotonic() - start, time.process_time() - cpu0
    print('STOP', flush=True)
    port.close()
    return {'scans': received / TELEGRAM, 'elapsed': elapsed, 'cpu': cpu, 'bad_crc': 0,
            'skipped': 0}


def measure(emulator, mode: str, seconds: float) -> dict:
    """Run one reader process; count what the emulator sent between its START and STOP."""
    child = subprocess.Popen([sys.executable, __file__, mode, emulator.path, str(seconds)],
                             stdout=subprocess.PIPE, text=True)
    assert child.stdout is not None
    line = child.stdout.readline().strip()
    if line != 'START':
        child.kill()
        raise SystemExit(f'bench: {mode} reader did not start (got {line!r})')
    sent0, dropped0 = emulator.scans_sent, emulator.bytes_dropped
    line = child.stdout.readline().strip()
    sent, dropped = emulator.scans_sent - sent0, emulator.bytes_dropped - dropped0
    output = child.stdout.read()
    child.wait(timeout=seconds + 30)
    if line != 'STOP' or child.returncode or not output.strip():
        raise SystemExit(f'bench: {mode} reader failed (exit {child.returncode}): {line!r}')
    result = json.loads(output.strip().splitlines()[-1])
    result.update(sent=sent, dropped=dropped)
    return result


def main() -> int:
    parser = argparse.ArgumentParser(description='SICK driver benchmark (500 kbaud, 361 values)')
    parser.add_argument('mode', nargs='?', choices=['driver', 'raw'], help=argparse.SUPPRESS)
    parser.add_argument('path', nargs='?', help=argparse.SUPPRESS)
    parser.add_argument('child_seconds', nargs='?', type=float, help=argparse.SUPPRESS)
    parser.add_argument('--seconds', type=float, default=10.0, help='seconds per reader')
    args = parser.parse_args()
    if args.mode:
        runner = run_driver if args.mode == 'driver' else run_raw
        print(json.dumps(runner(args.path, args.child_seconds)), flush=True)
        return 0

    from wurde_drivers.sick.emulator import SickEmulator
    emulator = SickEmulator(scan_source=lambda count, fov: [4.0] * count)
    with emulator:
        rows = [('SickLaser.poll', measure(emulator, 'driver', args.seconds))]
        # The device stays at 500000 baud in continuous mode after the driver closes the port.
        rows.append(('raw pyserial', measure(emulator, 'raw', args.seconds)))
        period = emulator.scan_period
    print(f'SICK LMS emulator on a pty: {BAUD} baud, {VALUES} values ({TELEGRAM}-byte telegrams), '
          f'paced at {1 / period:.1f} scans/s; {args.seconds:g} s per reader, each in its own '
          f'process')
    print(f'{"reader":<15} {"recv/s":>8} {"sent/s":>8} {"lost":>6} {"bad CRC":>8} '
          f'{"CPU ms/scan":>12} {"CPU %":>6}')
    for name, row in rows:
        received_rate = row['scans'] / row['elapsed']
        sent_rate = row['sent'] / row['elapsed']
        # The raw loop counts bytes, not telegrams: its "lost" would only be rounding.
        lost = f"{max(row['sent'] - round(row['scans']), 0)}" if name != 'raw pyserial' else '-'
        per_scan = 1000.0 * row['cpu'] / row['scans'] if row['scans'] else float('nan')
        print(f'{name:<15} {received_rate:>8.1f} {sent_rate:>8.1f} {lost:>6} {row["bad_crc"]:>8d} '
              f'{per_scan:>12.3f} {100.0 * row["cpu"] / row["elapsed"]:>6.1f}')
    driver, raw = rows[0][1], rows[1][1]
    if driver['scans'] and raw['scans']:
        ratio = (driver['cpu'] / driver['scans']) / (raw['cpu'] / raw['scans'])
        print(f'driver CPU per scan / raw pyserial CPU per scan: {ratio:.1f}x; '
              f'emulator bytes dropped (reader too slow): {driver["dropped"]} / {raw["dropped"]}')
    return 0


if __name__ == '__main__':
    sys.exit(main())
