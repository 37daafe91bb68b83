"""diffbot on a live ROS 2 graph: the course's nodes speaking DDS (extra ``live``: cyclonedds).

The nodes are classes shaped like rclpy's: make one, use it as a context manager (it cleans up on
the way out), :meth:`~diffbot.live.transport.Node.spin` it until a signal or call
:meth:`~diffbot.live.transport.Node.spin_once` from a loop of your own. Nothing here is imported
by ``import diffbot``; :mod:`diffbot.live.transport` is the only module that imports cyclonedds.
"""
