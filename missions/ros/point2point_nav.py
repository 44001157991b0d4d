"""Point-to-point navigation (seed 002, exercise 6): drive to each goal received on /goal.

A two-state machine: IDLE waits for a goal; GO_TO_GOAL steers toward it with a proportional
heading controller and slows down while misaligned, until the goal is within
``goal_tolerance``. The robot pose comes from TF (``odom`` -> ``base_link``).

Run it without ROS:
    baobab ros run missions/ros/point2point_nav.py --world walls \\
        --pub /goal geometry_msgs/msg/PoseStamped \\
        "{header: {frame_id: odom}, pose: {position: {x: 2.0, y: 2.0}}}" --at 1
"""

import math

import rclpy
import rclpy.time
from geometry_msgs.msg import PoseStamped, Twist
from rclpy.duration import Duration
from rclpy.node import Node
from tf2_ros import Buffer, TransformException, TransformListener


def angle_wrap(angle):
    """Wrap an angle to [-pi, pi]."""
    return math.atan2(math.sin(angle), math.cos(angle))


def yaw_from_quat(q):
    """Yaw (rad) of a geometry_msgs/Quaternion."""
    siny_cosp = 2.0 * (q.w * q.z + q.x * q.y)
    cosy_cosp = 1.0 - 2.0 * (q.y * q.y + q.z * q.z)
    return math.atan2(siny_cosp, cosy_cosp)


def clamp(value, low, high):
    """Limit value to [low, high]."""
    return max(low, min(high, value))


class Point2PointNav(Node):
    def __init__(self):
        super().__init__("point2point_nav")
        self.declare_parameter("world_frame", "odom")
        self.declare_parameter("base_frame", "base_link")
        self.declare_parameter("linear_speed", 0.20)
        self.declare_parameter("angular_speed", 0.6)
        self.declare_parameter("goal_tolerance", 0.05)
        self.world_frame = self.get_parameter("world_frame").value
        self.base_frame = self.get_parameter("base_frame").value
        self.linear_speed = self.get_parameter("linear_speed").value
        self.angular_speed = self.get_parameter("angular_speed").value
        self.goal_tolerance = self.get_parameter("goal_tolerance").value

        self.cmd_pub = self.create_publisher(Twist, "/cmd_vel", 10)
        self.goal_sub = self.create_subscription(PoseStamped, "/goal", self.on_goal, 10)
        self.tf_buffer = Buffer()
        self.tf_listener = TransformListener(self.tf_buffer, self)
        self.timer = self.create_timer(0.05, self.step)

        self.goal = None
        self.state = "IDLE"
        self.get_logger().info("point2point_nav ready, waiting for a goal on /goal")

    def get_pose(self):
        tf = self.tf_buffer.lookup_transform(
            target_frame=self.world_frame,
            source_frame=self.base_frame,
            time=rclpy.time.Time(),
            timeout=Duration(seconds=0.2),
        )
        t = tf.transform.translation
        return t.x, t.y, yaw_from_quat(tf.transform.rotation)

    def on_goal(self, msg):
        self.goal = msg
        self.state = "GO_TO_GOAL"
        p = msg.pose.position
        self.get_logger().info(f"New goal: ({p.x:.2f}, {p.y:.2f})")

    def goal_distance(self, x, y):
        gx, gy = self.goal.pose.position.x, self.goal.pose.position.y
        return math.hypot(gx - x, gy - y)

    def publish_cmd(self, vx, wz):
        cmd = Twist()
        cmd.linear.x = float(vx)
        cmd.angular.z = float(wz)
        self.cmd_pub.publish(cmd)

    def stop(self):
        self.publish_cmd(0.0, 0.0)

    def go_to_goal(self, x, y, yaw):
        gx, gy = self.goal.pose.position.x, self.goal.pose.position.y
        theta_d = math.atan2(gy - y, gx - x)
        theta_err = angle_wrap(theta_d - yaw)
        wz = clamp(1.5 * theta_err, -self.angular_speed, self.angular_speed)
        theta_max = math.radians(70.0)
        vx = self.linear_speed * max(0.0, 1.0 - abs(theta_err) / theta_max)
        self.publish_cmd(vx, wz)

    def step(self):
        if self.state != "GO_TO_GOAL":
            return
        try:
            x, y, yaw = self.get_pose()
        except TransformException as exc:
            self.get_logger().warning(f"No pose yet: {exc}")
            return
        if self.goal_distance(x, y) < self.goal_tolerance:
            self.stop()
            self.state = "IDLE"
            self.get_logger().info("Goal reached")
        else:
            self.go_to_goal(x, y, yaw)


def main(args=None):
    rclpy.init(args=args)
    node = Point2PointNav()
    try:
        rclpy.spin(node)
    except KeyboardInterrupt:
        pass
    node.stop()
    node.destroy_node()
    rclpy.try_shutdown()


if __name__ == "__main__":
    main()
