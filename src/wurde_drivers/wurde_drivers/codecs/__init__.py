"""Protocol codecs: pure functions over bytes (framing, CRC, encode, decode).

Codecs import neither rclpy nor wurde_core (DESIGN, "Who may import whom"); they are what the golden
and fuzz tests hit.
"""
