from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node


def generate_launch_description():
    topic_name = LaunchConfiguration("topic_name")
    timer_period = LaunchConfiguration("timer_period")
    return LaunchDescription(
        [
            DeclareLaunchArgument("topic_name", default_value="chatter", description="Topic"),
            DeclareLaunchArgument("timer_period", default_value="1.0", description="Period (s)"),
            Node(
                package="exercise_pub_sub",
                executable="pub_node",
                parameters=[{"topic_name": topic_name, "timer_period": timer_period}],
            ),
            Node(
                package="exercise_pub_sub",
                executable="sub_node",
                parameters=[{"topic_name": topic_name}],
            ),
        ]
    )
