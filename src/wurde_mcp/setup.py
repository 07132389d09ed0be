from setuptools import find_packages, setup

PACKAGE = 'wurde_mcp'

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
    description=("The Master Control Program: a lifecycle supervisor node that starts modules from mcp-config and "
                 "mcp-mappings, watches heartbeats, restarts and assigns streams (issue: wurde_mcp)."),
    license='BSD-3-Clause',
    tests_require=['pytest'],
    entry_points={'console_scripts': [
        'mcp = wurde_mcp.node:main',
        'turn_off = wurde_mcp.turn_off:turn_off',
        'mcp_controller = wurde_mcp.control:mcp_controller',
        'xml_server = wurde_mcp.xml_server.module:main',
        'record = wurde_mcp.recording.record:main',
        'replay = wurde_mcp.recording.replay:main',
        'live_view = wurde_mcp.recording.live_view:main',
        'param_daemon = wurde_mcp.carmen.daemon:main',
        'param_tool = wurde_mcp.carmen.tool:main',
        'map_server = wurde_mcp.carmen.map_server:main',
        'container = wurde_mcp.container.host:main',
    ]},
)
