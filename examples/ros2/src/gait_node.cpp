// A ROS 2 node that estimates gait with the yoyogait core, the C++ counterpart of
// `yoyogait live --ros2-topic` (docs/live.md). It is an example: it is not built with yoyogait.
//
// In:  geometry_msgs/msg/PoseStamped on "pelvis_pose": the pelvis (a rigid body or a marker
//      centre) from a motion-capture driver, in metres, frame with `up_axis` up.
// Out: std_msgs/msg/Float64MultiArray on "gait_estimate": dim[0] labelled "estimate", data =
//      the estimate stream's channels in their order (time_s, vx_mps, vz_mps, vh_a_mps, ...,
//      points_seen, valid, invalid_reason, input_noise_m), the layout of `yoyogait live --ros2-topic`.
//      Gate on valid (1): invalid_reason holds the InvalidReason bits when it is 0.
//      The Python node (`yoyogait ros2`, docs/ros2.md) publishes typed, stamped messages instead.
//
// The estimator's update() is noexcept and allocates nothing; the message is allocated once.
#include <array>
#include <memory>

#include <geometry_msgs/msg/pose_stamped.hpp>
#include <rclcpp/rclcpp.hpp>
#include <std_msgs/msg/float64_multi_array.hpp>
#include <yoyogait/online.hpp>

class GaitNode : public rclcpp::Node {
 public:
  GaitNode()
      : Node("yoyogait_gait"),
        estimator_(1, static_cast<int>(declare_parameter<int>("up_axis", 2)), 1.0) {  // one point, metres
    publisher_ = create_publisher<std_msgs::msg::Float64MultiArray>("gait_estimate", 10);
    subscription_ = create_subscription<geometry_msgs::msg::PoseStamped>(
        "pelvis_pose", rclcpp::SensorDataQoS(),
        [this](const geometry_msgs::msg::PoseStamped& pose) { on_pose(pose); });
    message_.layout.dim.resize(1);
    message_.layout.dim[0].label = "estimate";
    message_.layout.dim[0].size = kChannels;
    message_.layout.dim[0].stride = kChannels;
    message_.data.resize(kChannels);
  }

 private:
  static constexpr std::size_t kChannels = 26;  // the fields of OnlineEstimate, in the table's order

  void on_pose(const geometry_msgs::msg::PoseStamped& pose) {
    const double t_s = rclcpp::Time(pose.header.stamp).seconds();
    const std::array<double, 3> xyz{pose.pose.position.x, pose.pose.position.y, pose.pose.position.z};
    const yoyogait::OnlineEstimate e = estimator_.update(t_s, xyz.data());
    if (e.status == yoyogait::OnlineStatus::kTimeNotIncreasing) return;  // duplicated or out of order
    const std::array<double, kChannels> row{
        e.t_s, e.vx_mps, e.vz_mps, e.vh_a_mps, e.vh_b_mps, e.heading_rad, e.walk_a_mps, e.walk_b_mps,
        e.vx_hat_mps, e.vz_hat_mps, e.step_frequency_hz, e.step_frequency_std_hz, e.speed_mps, e.speed_std_mps,
        e.gait_phase, e.next_step_in_s, e.input_latency_s, e.estimate_age_s, static_cast<double>(e.status),
        static_cast<double>(e.estimator_status), e.walking ? 1.0 : 0.0, e.estimator_fed ? 1.0 : 0.0,
        static_cast<double>(e.points_seen), e.valid ? 1.0 : 0.0, static_cast<double>(e.invalid_reason),
        e.input_noise_m};
    std::copy(row.begin(), row.end(), message_.data.begin());
    publisher_->publish(message_);
  }

  yoyogait::OnlineEstimator estimator_;
  std_msgs::msg::Float64MultiArray message_;
  rclcpp::Publisher<std_msgs::msg::Float64MultiArray>::SharedPtr publisher_;
  rclcpp::Subscription<geometry_msgs::msg::PoseStamped>::SharedPtr subscription_;
};

int main(int argc, char** argv) {
  rclcpp::init(argc, argv);
  rclcpp::spin(std::make_shared<GaitNode>());
  rclcpp::shutdown();
  return 0;
}
