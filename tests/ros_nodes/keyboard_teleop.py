import rclpy
from geometry_msgs.msg import Twist
from pynput import keyboard
from rclpy.node import Node


class KeyboardTeleop(Node):
    def __init__(self):
        super().__init__("keyboard_teleop")
        self.declare_parameter("linear_speed", 0.25)
        self.declare_parameter("angular_speed", 1.2)
        self.linear_speed = self.get_parameter("linear_speed").value
        self.angular_speed = self.get_parameter("angular_speed").value
        self.pub = self.create_publisher(Twist, "cmd_vel", 10)
        self.allowed = ("w", "a", "s", "d")
        self.pressed = set()

    @staticmethod
    def key_to_char(key):
        try:
            return key.char.lower() if key.char else None
        except AttributeError:
            return None

    def on_press(self, key):
        char = self.key_to_char(key)
        if char not in self.allowed:
            return
        self.pressed.add(char)
        self.publish_cmd_vel()

    def on_release(self, key):
        char = self.key_to_char(key)
        if char not in self.allowed:
            return
        self.pressed.discard(char)
        self.publish_cmd_vel()

    def publish_cmd_vel(self):
        forward = ("w" in self.pressed) - ("s" in self.pressed)
        turn = ("a" in self.pressed) - ("d" in self.pressed)
        msg = Twist()
        msg.linear.x = self.linear_speed * forward
        msg.angular.z = self.angular_speed * turn
        self.pub.publish(msg)


def main(args=None):
    rclpy.init(args=args)
    node = KeyboardTeleop()
    listener = keyboard.Listener(on_press=node.on_press, on_release=node.on_release)
    listener.start()
    try:
        rclpy.spin(node)
    except KeyboardInterrupt:
        pass
    finally:
        listener.stop()
        node.destroy_node()
        rclpy.try_shutdown()


if __name__ == "__main__":
    main()
