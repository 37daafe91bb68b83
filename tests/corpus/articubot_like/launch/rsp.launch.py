# Publishes the robot's description (shape only; never run by the tests).
from launch import LaunchDescription


def generate_launch_description():
    return LaunchDescription([])
