from setuptools import find_packages, setup

PACKAGE = 'pluto_motion'

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
    description=("Pluto's movement chain: driveModule, avoidModule and motionModule with the Pluto document's "
                 "command flags and status codes."),
    license='BSD-3-Clause',
    tests_require=['pytest'],
    entry_points={'console_scripts': [
        'drive_module = pluto_motion.drive_module:main',
        'avoid_module = pluto_motion.avoid_module:main',
        'motion_module = pluto_motion.motion_module:main',
        'drive_i = pluto_motion.drive_i:main',
        'avoid_i = pluto_motion.avoid_i:main',
        'motion_i = pluto_motion.motion_i:main',
        # The other modules' keyboard programs (Pluto 5) over their proxies.
        'base_i = pluto_motion.base_i:main',
        'wrist_i = pluto_motion.wrist_i:main',
        'sick_i = pluto_motion.sick_i:main',
        'dmu_i = pluto_motion.dmu_i:main',
        'gpsmeter = pluto_motion.gpsmeter:main',
        'slam_i = pluto_motion.slam_i:main',
        'local_i = pluto_motion.local_i:main',
        'synchro_mover = pluto_motion.synchro_mover:main',
        'laser_avoider = pluto_motion.laser_avoider:main',
        'mission = pluto_motion.mission:main',
        'navigator = pluto_motion.navigator:main',
        # The guide's program names, so that its configurations run as printed (1.1.5, 10.1.1).
        'synchroMover = pluto_motion.synchro_mover:main',
        'vectorMover = pluto_motion.synchro_mover:main',
        'laserAvoider = pluto_motion.laser_avoider:main',
    ]},
)
