import numpy as np
import rclpy
from geometry_msgs.msg import PoseStamped
from rclpy.node import Node
from scipy.spatial.transform import Rotation as R
from scipy.spatial.transform import Slerp


class ExercisePosePublisher(Node):
    def __init__(self):
        super().__init__("exercise_pose_publisher")
        self.declare_parameter("goal", [5.0, 0.45, 0.2, 0.35, 1.0, 0.0, 0.0, 0.0])
        goal = np.array(self.get_parameter("goal").value)
        if goal.size != 8:
            raise ValueError(
                f"'goal' must have 8 values [T, x, y, z, qx, qy, qz, qw], got {goal.size}"
            )
        self.T = float(goal[0])
        if self.T <= 0.0:
            raise ValueError(f"the duration T must be > 0, got {self.T}")
        self.goal_pos = goal[1:4]
        quat = goal[4:8]
        norm = np.linalg.norm(quat)
        if norm < 1e-6:
            raise ValueError("the goal quaternion has a norm near zero")
        self.goal_quat = quat / norm

        self.rate_hz = 100.0
        self.dt = 1.0 / self.rate_hz
        self.t = 0.0
        self.start_pos = None
        self.start_quat = None
        self.frame_id = "panda_link0"
        self.sub = self.create_subscription(
            PoseStamped, "/cartesian_impedance/current_pose", self.current_pose_cb, 10
        )
        self.pub = self.create_publisher(PoseStamped, "/cartesian_impedance/desired_pose", 10)
        self.timer = self.create_timer(self.dt, self.timer_cb)

    def current_pose_cb(self, msg):
        if self.start_pos is None:
            p, q = msg.pose.position, msg.pose.orientation
            self.start_pos = np.array([p.x, p.y, p.z])
            self.start_quat = np.array([q.x, q.y, q.z, q.w])
            self.frame_id = msg.header.frame_id
            self.slerp = Slerp([0.0, 1.0], R.from_quat([self.start_quat, self.goal_quat]))
            self.get_logger().info("Start pose received, planning the trajectory")

    def timer_cb(self):
        if self.start_pos is None:
            return
        self.t = min(self.t + self.dt, self.T)
        alpha = self.t / self.T
        pos = (1.0 - alpha) * self.start_pos + alpha * self.goal_pos
        quat = self.slerp(alpha).as_quat()
        msg = PoseStamped()
        msg.header.stamp = self.get_clock().now().to_msg()
        msg.header.frame_id = self.frame_id
        msg.pose.position.x, msg.pose.position.y, msg.pose.position.z = (float(v) for v in pos)
        (
            msg.pose.orientation.x,
            msg.pose.orientation.y,
            msg.pose.orientation.z,
            msg.pose.orientation.w,
        ) = (float(v) for v in quat)
        self.pub.publish(msg)


def main(args=None):
    rclpy.init(args=args)
    node = ExercisePosePublisher()
    try:
        rclpy.spin(node)
    except KeyboardInterrupt:
        pass
    node.destroy_node()
    rclpy.try_shutdown()


if __name__ == "__main__":
    main()
