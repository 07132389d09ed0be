from setuptools import find_packages, setup

PACKAGE = 'wurde_core'

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
    description=("The WURDE programming model on rclpy: CommsManager, RobotObjects with data / info / request "
                 "channels, Writable locks, triggers, RoleConfiguration and Logger (issue: wurde_core)."),
    license='BSD-3-Clause',
    tests_require=['pytest'],
    entry_points={'console_scripts': [
        'foo_server = wurde_core.foo_server:main',
        'foo_client = wurde_core.foo_client:main',
        # The guide's program name (appendix 10.1.1), so that its configuration runs as printed.
        'fooServer = wurde_core.foo_server:main',
    ]},
)
