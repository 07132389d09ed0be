"""The user-defined Thermometer interface is generated, installed and used by two processes."""

from __future__ import annotations

from wurde_idl import load
from wurde_testing import ChildProcess, find_executable

def executable(name: str) -> str:
    return find_executable('wurde_example_thermometer', name)


def test_interface_is_registered_with_its_description() -> None:
    desc = load('Thermometer')
    assert desc['package'] == 'wurde_example_thermometer'
    assert [m['name'] for m in desc['info']] == ['alarm_celsius', 'positions']
    assert desc['info'][1]['type'] == 'Point3D' and desc['info'][1]['is_array']
    assert [m['name'] for m in desc['types']['ProbeReading']] == ['celsius', 'valid']


def test_generated_messages_use_builtin_and_local_types() -> None:
    from wurde_example_thermometer.msg import ThermometerData, ThermometerInfo

    assert ThermometerInfo.get_fields_and_field_types()['positions'] == \
        'sequence<wurde_interfaces/Point3D>'
    assert ThermometerData.get_fields_and_field_types()['readings'] == \
        'sequence<wurde_example_thermometer/ProbeReading>'
    assert 'reading_count' not in ThermometerData.get_fields_and_field_types()


def test_supplier_and_consumer_processes_exchange_readings(ros_domain: int) -> None:
    with ChildProcess([executable('thermometer_consumer'), '--count', '15']) as consumer, \
            ChildProcess([executable('thermometer_supplier'), '--count', '15', '--rate', '50']):
        code = consumer.process.wait(timeout=60)
        consumer.stop()
    assert code == 0, consumer.stdout + consumer.stderr
    assert 'info from thermometer_supplier: alarm at 30.0 C' in consumer.stdout
    lines = consumer.stdout.splitlines()
    assert len([line for line in lines if line.startswith('data ')]) == 15
    assert 'received 15 of 15 readings' in consumer.stdout
