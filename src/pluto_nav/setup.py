from setuptools import find_packages, setup

PACKAGE = 'pluto_nav'

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
    description=("Pluto's localization: localModule with its five pose streams, poseModule, slamModule and the "
                 "loc proxy."),
    license='BSD-3-Clause',
    tests_require=['pytest'],
    entry_points={'console_scripts': [
        'local_module = pluto_nav.local_module:main',
        'pose_module = pluto_nav.pose_module:main',
        'pose_i = pluto_nav.pose_i:main',
        'slam_module = pluto_nav.slam_module:main',
        'offline_nav = pluto_nav.offline_nav:main',
        'slam_score = pluto_nav.slam_score:main',
        'carmen_log = pluto_nav.carmen_log:main',
    ]},
)
