# Starts the two-wheel base with mock hardware (shape only; never run by the tests).
from launch import LaunchDescription


def generate_launch_description():
    return LaunchDescription([])
