from setuptools import find_packages, setup

PACKAGE = 'wurde_drivers'

setup(
    name=PACKAGE,
    version='0.1.0',
    packages=find_packages(exclude=['test']),
    data_files=[
        ('share/ament_index/resource_index/packages', [f'resource/{PACKAGE}']),
        (f'share/{PACKAGE}', ['package.xml']),
    ],
    package_data={PACKAGE: ['py.typed']},
    install_requires=['setuptools'],
    zip_safe=True,
    maintainer='WURDE-on-ROS 2 team',
    maintainer_email='wurde@example.org',
    description="Device drivers that speak the real protocols (SICK, rFLEX, PTU, CAN wrist, GPS, DMU), their device emulators, and the simulated Pluto robot (issues: drivers, simulated robot).",
    license='BSD-3-Clause',
    tests_require=['pytest'],
    entry_points={'console_scripts': [
        f'{name} = {PACKAGE}.modules.{name}:main' for name in (
            'dummy_base', 'dummy_sick', 'dummy_wrist', 'dummy_dmu', 'dummy_gps', 'tour',
            'sick_server', 'sick_emulator', 'rflex_server', 'rflex_emulator', 'ptu_server',
            'ptu_emulator', 'gps_module', 'gps_emulator', 'dmu_module', 'dmu_emulator',
            'wrist_module')]},
)
