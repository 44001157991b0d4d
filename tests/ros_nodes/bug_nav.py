import math

import rclpy
import rclpy.time
from geometry_msgs.msg import PoseStamped, Twist
from rclpy.duration import Duration
from rclpy.node import Node
from rclpy.qos import qos_profile_sensor_data
from sensor_msgs.msg import LaserScan
from tf2_ros import Buffer, TransformException, TransformListener


def angle_wrap(angle):
    return math.atan2(math.sin(angle), math.cos(angle))


def yaw_from_quat(q):
    return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))


def clamp(value, low, high):
    return max(low, min(high, value))


class BugNav(Node):
    def __init__(self):
        super().__init__("bug_nav")
        self.declare_parameter("world_frame", "odom")
        self.declare_parameter("base_frame", "base_link")
        self.declare_parameter("linear_speed", 0.20)
        self.declare_parameter("angular_speed", 0.6)
        self.declare_parameter("goal_tolerance", 0.05)
        self.declare_parameter("wall_dist", 0.4)
        self.declare_parameter("mline_tol", 0.1)
        self.world_frame = self.get_parameter("world_frame").value
        self.base_frame = self.get_parameter("base_frame").value
        self.linear_speed = self.get_parameter("linear_speed").value
        self.angular_speed = self.get_parameter("angular_speed").value
        self.goal_tolerance = self.get_parameter("goal_tolerance").value
        self.wall_dist = self.get_parameter("wall_dist").value
        self.mline_tol = self.get_parameter("mline_tol").value

        self.cmd_pub = self.create_publisher(Twist, "/cmd_vel", 10)
        self.goal_sub = self.create_subscription(PoseStamped, "/goal", self.on_goal, 10)
        self.scan_sub = self.create_subscription(
            LaserScan, "/scan", self.on_scan, qos_profile_sensor_data
        )
        self.tf_buffer = Buffer()
        self.tf_listener = TransformListener(self.tf_buffer, self)
        self.timer = self.create_timer(0.05, self.step)

        self.goal = None
        self.scan = None
        self.start = None
        self.hit_point = None
        self.hit_goal_dist = None
        self.left_mline = False
        self.state = "IDLE"

    def get_pose(self):
        tf = self.tf_buffer.lookup_transform(
            self.world_frame, self.base_frame, rclpy.time.Time(), timeout=Duration(seconds=0.2)
        )
        t = tf.transform.translation
        return t.x, t.y, yaw_from_quat(tf.transform.rotation)

    def on_goal(self, msg):
        self.goal = msg
        x, y, _ = self.get_pose()
        self.start = (x, y)
        self.hit_point = None
        self.hit_goal_dist = None
        self.left_mline = False
        self.state = "GO_TO_GOAL"

    def on_scan(self, msg):
        self.scan = msg

    def goal_distance(self, x, y):
        return math.hypot(self.goal.pose.position.x - x, self.goal.pose.position.y - y)

    def min_range_in_sector(self, center_deg, half_width_deg):
        ranges = self.scan.ranges
        inc = self.scan.angle_increment
        start = math.radians(center_deg - half_width_deg) % (2 * math.pi)
        end = math.radians(center_deg + half_width_deg) % (2 * math.pi)
        i_start = round(start / inc) % len(ranges)
        i_end = round(end / inc) % len(ranges)
        if i_start <= i_end:
            values = ranges[i_start : i_end + 1]
        else:
            values = list(ranges[: i_end + 1]) + list(ranges[i_start:])
        return min(values)

    def front_dist(self):
        return self.min_range_in_sector(0.0, 30.0)

    def left_dist(self):
        return self.min_range_in_sector(60.0, 20.0)

    def dist_to_mline(self, x, y):
        (sx, sy) = self.start
        gx, gy = self.goal.pose.position.x, self.goal.pose.position.y
        a, b = gy - sy, sx - gx
        c = -(a * sx + b * sy)
        return abs(a * x + b * y + c) / math.hypot(a, b)

    def publish_cmd(self, vx, wz):
        cmd = Twist()
        cmd.linear.x = float(vx)
        cmd.angular.z = float(wz)
        self.cmd_pub.publish(cmd)

    def stop(self):
        self.publish_cmd(0.0, 0.0)

    def go_to_goal(self, x, y, yaw):
        gx, gy = self.goal.pose.position.x, self.goal.pose.position.y
        err = angle_wrap(math.atan2(gy - y, gx - x) - yaw)
        wz = clamp(1.5 * err, -self.angular_speed, self.angular_speed)
        vx = self.linear_speed * max(0.0, 1.0 - abs(err) / math.radians(70.0))
        self.publish_cmd(vx, wz)

    def follow_left_wall(self):
        if self.front_dist() < self.wall_dist:
            self.publish_cmd(0.0, -self.angular_speed)
        elif self.left_dist() > 1.25 * self.wall_dist:
            self.publish_cmd(0.0, self.angular_speed)
        else:
            self.publish_cmd(self.linear_speed, 0.0)

    def step(self):
        if self.state == "IDLE" or self.goal is None or self.scan is None:
            return
        try:
            x, y, yaw = self.get_pose()
        except TransformException:
            return
        d = self.goal_distance(x, y)
        if d < self.goal_tolerance:
            self.stop()
            self.state = "IDLE"
            self.get_logger().info("Goal reached")
            return
        if self.state == "GO_TO_GOAL" and self.front_dist() < self.wall_dist:
            self.hit_point, self.hit_goal_dist = (x, y), d
            self.left_mline = False
            self.state = "WALL_FOLLOW"
            self.get_logger().info(f"Hit point ({x:.2f}, {y:.2f})")
        elif self.state == "WALL_FOLLOW":
            on_mline = self.dist_to_mline(x, y) < self.mline_tol
            if not on_mline:
                self.left_mline = True
            elif self.left_mline and d < self.hit_goal_dist:
                self.state = "GO_TO_GOAL"
                self.get_logger().info(f"Leave point ({x:.2f}, {y:.2f})")
        if self.state == "GO_TO_GOAL":
            self.go_to_goal(x, y, yaw)
        else:
            self.follow_left_wall()


def main(args=None):
    rclpy.init(args=args)
    node = BugNav()
    try:
        rclpy.spin(node)
    except KeyboardInterrupt:
        pass
    node.destroy_node()
    rclpy.try_shutdown()


if __name__ == "__main__":
    main()
