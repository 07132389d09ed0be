"""What upstream ROS 2 Jazzy's tf2_msgs/msg/TFMessage is, as recorded from public sources.

The stand-in is right when these hold for it; tests compare against them, never against the
stand-in's own output.

- ``DEFINITION``: the text of ``tf2_msgs/msg/TFMessage.msg`` in ros2/geometry2 (jazzy), one line
  of 44 bytes with its newline: rosidl embeds it as the type's raw source, of length 44, in the
  generated description file named below.
- ``TYPE_HASH``: the RIHS01 hash of ``tf2_msgs/msg/TFMessage`` as rosidl generates it for
  upstream's package.  Source: a public colcon build of geometry2's tf2_msgs against
  ``/opt/ros/jazzy`` (its CMakeCache names only ``/opt/ros/jazzy`` prefixes), committed on GitHub
  in kuenem/Group-12_MotionPlanning-New at e45e9e5abd5e23ce7fbe568cae54560365db606b,
  ``build/tf2_msgs/rosidl_generator_c/tf2_msgs/msg/detail/tf_message__description.c``, function
  ``tf2_msgs__msg__TFMessage__get_type_hash``: ``{1, {0xe3, 0x69, 0xd0, 0xf0, ...}}``.  A second,
  independent generated file of another public package that nests TFMessage states the same
  value as ``tf2_msgs__msg__TFMessage__EXPECTED_HASH``.  The geometry_msgs, std_msgs and
  builtin_interfaces hashes in those files equal the PyPI wheels' ones (``REFERENCED_HASHES``).
"""

TYPE_NAME = 'tf2_msgs/msg/TFMessage'
DEFINITION = b'geometry_msgs/TransformStamped[] transforms\n'
TYPE_HASH = 'RIHS01_e369d0f05a23ae52508854b66f6aa0437f3449d652e8cbf22d5abe85d020f087'

#: The hashes of the types TFMessage refers to, from the same generated file.
REFERENCED_HASHES = {
    'builtin_interfaces/msg/Time':
        'RIHS01_b106235e25a4c5ed35098aa0a61a3ee9c9b18d197f398b0e4206cea9acf9c197',
    'geometry_msgs/msg/Quaternion':
        'RIHS01_8a765f66778c8ff7c8ab94afcc590a2ed5325a1d9a076ffff38fbce36f458684',
    'geometry_msgs/msg/Transform':
        'RIHS01_beb83fbe698636351461f6f35d1abb20010c43d55374d81bd041f1ba2581fddc',
    'geometry_msgs/msg/TransformStamped':
        'RIHS01_0a241f87d04668d94099cbb5ba11691d5ad32c2f29682e4eb5653424bd275206',
    'geometry_msgs/msg/Vector3':
        'RIHS01_cc12fe83e4c02719f1ce8070bfd14aecd40f75a96696a67a2a1f37f7dbb0765d',
    'std_msgs/msg/Header':
        'RIHS01_f49fb3ae2cf070f793645ff749683ac6b06203e41c891e17701b1cb597ce6a01',
}
