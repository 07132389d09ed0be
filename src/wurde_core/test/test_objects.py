"""RobotObject API and bad input, in one process (the manager talks to itself over DDS)."""

from __future__ import annotations

import subprocess
import sys

import pytest

from conftest import HERE, until
from wurde_core import (CommsManager, DirectionError, LockedError, LockMode, NotRegisteredError,
                        Pose, RegistrationError, RunState, Time, UnknownInterfaceError, WurdeError,
                        global_configuration)
from wurde_core.errors import InvalidTypeError, InvalidValueError, MemberError
from wurde_core.interfaces import Egomotion, Foo, robot_object_class


def test_registering_twice_is_refused(manager: CommsManager) -> None:
    foo = Foo('twice')
    manager.register_supplier(foo)
    with pytest.raises(RegistrationError, match=r'Foo\("twice"\) is already registered as a '
                       'supplier with this CommsManager'):
        manager.register_consumer(foo)


def test_direction_is_enforced(manager: CommsManager) -> None:
    consumer = Foo('direction')
    manager.register_consumer(consumer)
    with pytest.raises(DirectionError, match='only a supplier may publish info'):
        consumer.publish_info()
    with pytest.raises(DirectionError, match='only a supplier may publish data'):
        consumer.publish_data()
    with pytest.raises(DirectionError, match="consumer's info is read-only"):
        consumer.info.max_range.set_value(1.0)
    supplier = Foo('direction2')
    manager.register_supplier(supplier)
    with pytest.raises(DirectionError, match='only a consumer may publish requests'):
        supplier.publish_request()
    with pytest.raises(NotRegisteredError, match='register it with a CommsManager'):
        Foo('loose').publish_data()


def test_supplier_may_not_write_a_member_locked_to_consumers(manager: CommsManager) -> None:
    foo = Foo('consumers_only')
    manager.register_supplier(foo)
    foo.info.angle_max.lock(LockMode.CONSUMERS)
    assert foo.info.angle_max.locked() == (LockMode.CONSUMERS, '')
    with pytest.raises(LockedError, match='angle_max is locked to consumers only'):
        foo.info.angle_max.set_value(1.0)
    foo.info.angle_max.unlock()
    foo.info.angle_max.set_value(1.0)
    foo.lock(LockMode.PROCESS, 'Somebody')
    with pytest.raises(LockedError, match='locked to process "Somebody"'):
        foo.info.max_range.set_value(2.0)


def test_unknown_interface_names_the_installed_ones() -> None:
    with pytest.raises(UnknownInterfaceError, match='unknown interface "Fooo"; installed: .*Foo'):
        robot_object_class('Fooo')
    with pytest.raises(ImportError):
        from wurde_core.interfaces import NoSuchInterface  # noqa: F401


def test_an_unknown_interface_is_not_an_attribute_of_the_interfaces_module() -> None:
    import wurde_core.interfaces as interfaces
    assert hasattr(interfaces, 'Foo')
    assert not hasattr(interfaces, 'NoSuchInterface')
    with pytest.raises(WurdeError, match='unknown interface "NoSuchInterface"; installed: .*Foo'):
        interfaces.NoSuchInterface  # noqa: B018


def test_a_typo_on_a_member_raises_instead_of_passing_silently() -> None:
    foo = Foo('typo')
    with pytest.raises(AttributeError, match="FooData has no member 'rangs'; members: ranges"):
        foo.data.rangs = [1.0]
    with pytest.raises(AttributeError, match="has no member 'rangs'"):
        foo.data.rangs  # noqa: B018
    with pytest.raises(AttributeError, match="FooInfo has no member 'max_rang'"):
        foo.info.max_rang = 1.0
    with pytest.raises(MemberError, match="use info.max_range.set_value"):
        foo.info.max_range = 1.0
    foo.data.ranges = [1.0]
    foo.data.timestamp = Time(5.0)
    assert foo.data.ranges[0] == 1.0 and foo.data.timestamp == 5.0


def test_argument_errors_are_wurde_errors_of_the_usual_python_kind(ros_domain: int) -> None:
    with pytest.raises(InvalidValueError):
        CommsManager('')
    with pytest.raises(InvalidTypeError):
        Foo('')
    manager = CommsManager('Arguments')
    try:
        with pytest.raises(InvalidTypeError):
            manager.register_supplier(object())  # type: ignore[arg-type]
        supplier = Foo('arguments')
        with pytest.raises(InvalidValueError):
            supplier.set_lock('', LockMode.PROCESS)
    finally:
        manager.clean_up()
    for error in (InvalidValueError, InvalidTypeError, MemberError):
        assert issubclass(error, WurdeError)
    assert issubclass(InvalidValueError, ValueError) and issubclass(InvalidTypeError, TypeError)


def test_unknown_member_names_the_members() -> None:
    with pytest.raises(AttributeError, match='has no member .maxRange.; members: ranges'):
        Foo('m').data.maxRange  # noqa: B018
    with pytest.raises(AttributeError, match='use info.max_range.set_value'):
        Foo('m').info.max_range = 3.0


def test_data_info_and_header_round_trip_in_one_process(manager: CommsManager) -> None:
    supplier, consumer = Egomotion('ego'), Egomotion('ego')
    supplier.set_queue_mode(True)
    consumer.set_queue_mode(True)
    manager.register_supplier(supplier)
    manager.register_consumer(consumer)
    until(manager, lambda: supplier.peers() > 0, what='match')
    supplier.data.location = Pose(1.0, 2.0, 0.5)
    supplier.data.location.theta(0.75)
    supplier.data.tv = 0.3
    before = Time.now()
    assert supplier.publish_data()
    supplier.set_auto_tag(False)
    supplier.set_auto_timestamp(False)
    supplier.data.source = 'Mimic'
    supplier.data.timestamp = Time(12.5)
    assert supplier.publish_data()
    until(manager, lambda: consumer.received('data') == 2, what='two events')
    assert consumer.get_next_data()
    assert consumer.data.location == Pose(1.0, 2.0, 0.75)
    assert consumer.data.tv == pytest.approx(0.3)
    assert consumer.data.source == 'Tester' and consumer.data.timestamp >= before
    assert consumer.get_next_data()
    assert consumer.data.source == 'Mimic' and consumer.data.timestamp == Time(12.5)
    assert not consumer.get_next_data()


def test_nothing_flows_in_idle(manager: CommsManager) -> None:
    foo = Foo('idle')
    manager.register_supplier(foo)
    manager.set_state(RunState.IDLE)
    assert manager.step() == RunState.IDLE
    assert foo.publish_data() is False and foo.suppressed == 1
    manager.set_run()
    assert foo.publish_data() is True


def test_user_options_reach_the_global_configuration(ros_domain: int) -> None:
    manager = CommsManager('Opt')
    try:
        opts = manager.parse_options(['prog', '-c', 'laser.xml', '-a', '-n', 'Renamed', 'rest'],
                                     'c:ab')
        assert manager.name == 'Renamed' and opts.arguments == ['rest']
        config = global_configuration()
        assert config.get_option('c') == 'laser.xml' and config.get_option('a') == 'true'
        assert not config.have_option('b')
    finally:
        manager.clean_up()


def run_module(*args: str) -> subprocess.CompletedProcess[str]:
    code = ('import sys; from wurde_core import CommsManager; '
            'CommsManager("M").parse_options(sys.argv, "c:")')
    return subprocess.run([sys.executable, '-c', code, *args], capture_output=True, text=True,
                          timeout=60, check=False, cwd=HERE)


@pytest.mark.process
def test_wrong_option_prints_usage_and_exits_2() -> None:
    result = run_module('-z')
    assert result.returncode == 2
    assert 'option -z not recognized' in result.stderr and 'usage:' in result.stderr
    result = run_module('-c')
    assert result.returncode == 2 and 'option -c requires argument' in result.stderr


@pytest.mark.process
def test_bad_role_config_is_refused_with_file_and_line(tmp_path) -> None:
    bad = tmp_path / 'bad.xml'
    bad.write_text('<wurde-config>\n<log level="x"\n</wurde-config>\n')
    result = run_module('-g', str(bad))
    assert result.returncode == 2
    assert f'{bad}:3: not well-formed XML' in result.stderr
    result = run_module('-g', str(tmp_path / 'missing.xml'))
    assert result.returncode == 2 and 'missing.xml: cannot read' in result.stderr


def test_an_object_can_be_unregistered_and_registered_again(manager: CommsManager) -> None:
    foo = Foo('again')
    manager.register_supplier(foo)
    assert foo.is_connected() and foo in manager.objects(user_only=True)
    manager.unregister(foo)
    assert not foo.is_connected() and foo.role is None
    assert foo not in manager.objects(user_only=True)
    with pytest.raises(RegistrationError, match='is not registered'):
        manager.unregister(foo)
    manager.register_consumer(foo)
    assert foo.role == 'consumer' and foo.is_connected()
