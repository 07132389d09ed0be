from setuptools import find_packages, setup

PACKAGE = 'wurde_drivers'

#: Executable name -> module (inside the package) whose ``main`` it runs.
EXECUTABLES = {
    'dummy_base': 'sim.dummies.base',
    'dummy_sick': 'sim.dummies.sick',
    'dummy_wrist': 'sim.dummies.wrist',
    'dummy_dmu': 'sim.dummies.dmu',
    'dummy_gps': 'sim.dummies.gps',
    'tour': 'sim.tour',
    'sick_server': 'sick.module',
    'sick_emulator': 'sick.emulator_module',
    'rflex_server': 'rflex.module',
    'rflex_emulator': 'rflex.emulator_module',
    'ptu_server': 'ptu.module',
    'ptu_emulator': 'ptu.emulator_module',
    'gps_module': 'gps.module',
    'gps_emulator': 'gps.emulator_module',
    'dmu_module': 'dmu.module',
    'dmu_emulator': 'dmu.emulator_module',
    'wrist_module': 'wrist.module',
    'vision_module': 'vision.module',
    'eye': 'eye.module',
    'joystick_emulator': 'joystick.emulator_module',
    'blind_teleop': 'blind_teleop.program',
    'ros_inputs': 'ros_inputs.module',
    # The guide's program name, so that its configurations run as printed (1.1.5).
    'blindTeleop': 'blind_teleop.program',
    # The guide's driver names: chapter 1's (1.1.5) and the appendix's (10.1.1).
    'sickServer': 'sick.module',
    'sickLaser': 'sick.module',
    'rFlexServerII': 'rflex.module',
    'rFlexServer': 'rflex.module',
    'safePTUserver': 'ptu.module',
    'visionModule': 'vision.module',
}

#: The shipped vision operators (WURDE guide 7.2.3), found by type name (wurde_drivers.vision.registry).
VISION_OPERATORS = {
    'ImageWriter': 'vision.operators.image_writer:ImageWriter',
    'ImagePublisher': 'vision.operators.image_publisher:ImagePublisher',
    'StereoDataCollector': 'vision.operators.stereo_collector:StereoDataCollector',
}

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
    description=("Device drivers that speak the real protocols (SICK, rFLEX, PTU, CAN wrist, GPS, DMU), their "
                 "device emulators, and the simulated Pluto robot (issues: drivers, simulated robot)."),
    license='BSD-3-Clause',
    tests_require=['pytest'],
    entry_points={
        'console_scripts': [f'{name} = {PACKAGE}.{module}:main' for name, module in EXECUTABLES.items()],
        'wurde.vision_operators': [f'{name} = {PACKAGE}.{target}'
                                   for name, target in VISION_OPERATORS.items()],
    },
)
