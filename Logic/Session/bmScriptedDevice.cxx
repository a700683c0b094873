#include "bmScriptedDevice.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>

#include <Eigen/Geometry>

#include "bmVirtualCoupling.h"
#include "bmCsv.h"

namespace bm {

namespace {
constexpr double kPi = 3.14159265358979323846;
} // namespace

const char* ToString(ScriptMode m) {
  switch (m) {
  case ScriptMode::Feed:
    return "feed";
  case ScriptMode::Force:
    return "force";
  case ScriptMode::Trajectory:
    return "trajectory";
  case ScriptMode::Hand:
    return "hand";
  }
  return "?";
}

namespace {
constexpr double kMaxTrajectoryS = 3600;   ///< the longest session bmsim runs (--duration), s
constexpr double kMaxTrajectoryMm = 10000; ///< the reach of a scene (entry point limit), mm
} // namespace

std::vector<TrajectorySample> LoadTrajectoryCsv(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) // a FIFO would block the read
    throw std::runtime_error("trajectory '" + path + "' is not a regular file");
  std::ifstream in(path);
  if (!in)
    throw std::runtime_error("cannot read trajectory '" + path + "'");
  std::vector<TrajectorySample> out;
  std::string line;
  int lineNo = 0;
  while (std::getline(in, line)) {
    ++lineNo;
    if (line.empty() || line[0] == '#' || std::isalpha(static_cast<unsigned char>(line[0])))
      continue;
    const std::vector<double> v = ParseCsvNumbers(line, path + ":" + std::to_string(lineNo));
    if (v.size() != 4 && v.size() != 8)
      throw std::runtime_error(path + ":" + std::to_string(lineNo) + ": needs 4 or 8 columns");
    const std::string where = path + ":" + std::to_string(lineNo);
    for (size_t c = 0; c < v.size(); ++c)
      if (!std::isfinite(v[c]))
        throw std::runtime_error(where + ": column " + std::to_string(c + 1) +
                                 " is not a finite number");
    if (!(v[0] >= 0 && v[0] <= kMaxTrajectoryS))
      throw std::runtime_error(where + ": time_s must be in [0, 3600] s, got " +
                               std::to_string(v[0]));
    for (int c = 1; c <= 3; ++c)
      if (!(std::abs(v[size_t(c)]) <= kMaxTrajectoryMm))
        throw std::runtime_error(where + ": position must be within +-10000 mm, got " +
                                 std::to_string(v[size_t(c)]));
    TrajectorySample s;
    s.timeS = v[0];
    s.positionMm = {v[1], v[2], v[3]};
    if (v.size() == 8) {
      const Eigen::Quaterniond q(v[4], v[5], v[6], v[7]);
      if (!(q.norm() > 1e-6))
        throw std::runtime_error(where + ": the quaternion (qw, qx, qy, qz) is zero");
      s.rotation = q.normalized().toRotationMatrix();
    }
    if (!out.empty() && !(s.timeS > out.back().timeS))
      throw std::runtime_error(path + ":" + std::to_string(lineNo) + ": times must increase");
    out.push_back(s);
  }
  if (out.size() < 2)
    throw std::runtime_error("trajectory '" + path +
                             "' needs at least 2 samples (a start and an end time)");
  return out;
}

ScriptedDevice::ScriptedDevice(const ScriptedDeviceOptions& o) : O_(o) {
  O_.axis.normalize();
  if (O_.mode == ScriptMode::Trajectory) {
    if (O_.trajectory.empty())
      throw std::invalid_argument("scripted device: empty trajectory");
    for (size_t i = 1; i < O_.trajectory.size(); ++i)
      if (!(O_.trajectory[i].timeS > O_.trajectory[i - 1].timeS))
        throw std::invalid_argument("scripted device: trajectory times must increase");
  }
  if (!(O_.massKg > 0))
    throw std::invalid_argument("scripted device: mass must be > 0");
  if (!(O_.reactionS >= 0 && O_.reactionS <= 2))
    throw std::invalid_argument("scripted device: the reaction time must be in [0, 2] s");
  if (!(O_.holdDampingNsPerMm > 0 && O_.holdDampingNsPerMm <= 1))
    throw std::invalid_argument("scripted device: the holding damping must be in (0, 1] N s/mm");
  if (O_.mode == ScriptMode::Force || O_.mode == ScriptMode::Hand) {
    if (!(O_.appliedForceN >= 0 && O_.appliedForceN <= O_.limits.maxForceN)) {
      std::ostringstream m;
      m << "scripted device: applied force must be in [0, " << O_.limits.maxForceN
        << "] N (the device's maximum force), not " << O_.appliedForceN;
      throw std::invalid_argument(m.str());
    }
  }
  if (O_.mode == ScriptMode::Hand) {
    if (!(O_.handRampS >= 0 && O_.handRampS <= 60))
      throw std::invalid_argument("scripted device: hand ramp must be in [0, 60] s");
    if (!(O_.handTremorN >= 0 && O_.handTremorN <= 0.5 * O_.limits.maxForceN))
      throw std::invalid_argument(
          "scripted device: hand tremor must be in [0, half the device's maximum force] N");
    std::mt19937_64 rng(O_.handSeed);
    std::uniform_real_distribution<double> phase(0, 2 * kPi), tremorHz(8, 12), waverHz(0.3, 0.7);
    Waver_.push_back({0.1, waverHz(rng), phase(rng)});
    for (auto* v : {&TremorU_, &TremorV_})
      for (int i = 0; i < 3; ++i)
        v->push_back({O_.handTremorN / 3.0, tremorHz(rng), phase(rng)});
    // Two unit directions across the axis.
    const Eigen::Vector3d ref =
        std::abs(O_.axis(0)) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
    U_ = O_.axis.cross(ref).normalized();
    V_ = O_.axis.cross(U_).normalized();
  }
  Pose_ = PoseAt(0);
}

DevicePose ScriptedDevice::PoseAt(double t) const {
  DevicePose p;
  switch (O_.mode) {
  case ScriptMode::Feed:
    p.positionMm = O_.startMm - O_.axis * (O_.feedMmPerRev * O_.speedRpm / 60.0 * t);
    p.rotation = O_.rotation;
    break;
  case ScriptMode::Force:
  case ScriptMode::Hand:
    p = Pose_;
    if (t == 0) {
      p.positionMm = O_.startMm;
      p.rotation = O_.rotation;
    }
    break;
  case ScriptMode::Trajectory: {
    const auto& tr = O_.trajectory;
    auto it = std::upper_bound(tr.begin(), tr.end(), t,
                               [](double x, const TrajectorySample& s) { return x < s.timeS; });
    if (it == tr.begin()) {
      p.positionMm = tr.front().positionMm;
      p.rotation = tr.front().rotation;
      p.buttons = tr.front().buttons;
    } else if (it == tr.end()) {
      p.positionMm = tr.back().positionMm;
      p.rotation = tr.back().rotation;
      p.buttons = tr.back().buttons;
    } else {
      const TrajectorySample& a = *(it - 1);
      const TrajectorySample& b = *it;
      const double u = (t - a.timeS) / (b.timeS - a.timeS);
      p.positionMm = (1 - u) * a.positionMm + u * b.positionMm;
      p.rotation = Eigen::Quaterniond(a.rotation)
                       .slerp(u, Eigen::Quaterniond(b.rotation))
                       .toRotationMatrix();
      p.buttons = a.buttons;
    }
    break;
  }
  }
  return p;
}

double ScriptedDevice::Release(double t) const {
  constexpr double kLetGoS = 0.05; // the push falls to zero over this, s
  if (FeltAt_ < 0 || t < FeltAt_ + O_.reactionS)
    return 1.0;
  return std::max(0.0, 1.0 - (t - FeltAt_ - O_.reactionS) / kLetGoS);
}

Eigen::Vector3d ScriptedDevice::HandForce(double t) const {
  if (O_.mode == ScriptMode::Force)
    return -O_.axis * O_.appliedForceN * Release(t);
  if (O_.mode != ScriptMode::Hand)
    return Eigen::Vector3d::Zero();
  auto sum = [t](const std::vector<Sine>& v) {
    double x = 0;
    for (const Sine& s : v)
      x += s.amplitude * std::sin(2 * kPi * s.hz * t + s.phase);
    return x;
  };
  const double ramp =
      O_.handRampS > 0 && t < O_.handRampS ? 0.5 * (1 - std::cos(kPi * t / O_.handRampS)) : 1.0;
  const double push = O_.appliedForceN * ramp * (1.0 + sum(Waver_)) * Release(t);
  const Eigen::Vector3d f = -O_.axis * push + ramp * (U_ * sum(TremorU_) + V_ * sum(TremorV_));
  return VirtualCoupling::Clamp(f, O_.limits.maxForceN); // within the device's range
}

void ScriptedDevice::Advance(double timeS, double dtS) {
  if (O_.mode == ScriptMode::Force || O_.mode == ScriptMode::Hand) {
    // Semi-implicit Euler: m dv/dt = F_applied + F_device - c v (N, kg, mm/s: 1 N/kg = 1000
    // mm/s^2).
    if (O_.stopAtBreakthrough && FeltAt_ < 0) {
      // The resistance the device renders along the axis (out of the bone): once it held half
      // the push, its fall below half its peak is the breakthrough a trained hand feels.
      const double resist = Force_.dot(O_.axis);
      PeakResist_ = std::max(PeakResist_, resist);
      if (PeakResist_ >= 0.5 * O_.appliedForceN && resist < 0.5 * PeakResist_)
        FeltAt_ = timeS;
    }
    const Eigen::Vector3d f = HandForce(timeS) + Force_;
    const bool holding = FeltAt_ >= 0 && timeS >= FeltAt_ + O_.reactionS;
    const double m = O_.massKg,
                 c = (holding ? O_.holdDampingNsPerMm : O_.dampingNsPerMm) * 1000.0; // N s/m
    Velocity_ = (Velocity_ + dtS * 1000.0 * f / m) / (1.0 + dtS * c / m);
    Pose_.positionMm += Velocity_ * dtS;
    Pose_.rotation = O_.rotation;
  } else {
    Pose_ = PoseAt(timeS);
  }
  Time_ = timeS;
}

DeviceStatus ScriptedDevice::Read(DevicePose& pose) {
  if (O_.silentAtS >= 0 && Time_ >= O_.silentAtS)
    return DeviceStatus::NoResponse;
  if (O_.errorAtS >= 0 && Time_ >= O_.errorAtS) {
    Error_ = "scripted fault at t = " + std::to_string(O_.errorAtS) + " s";
    return DeviceStatus::Error;
  }
  pose = Pose_;
  return DeviceStatus::Ok;
}

DeviceStatus ScriptedDevice::Write(const Eigen::Vector3d& forceN) {
  Force_ = forceN;
  return DeviceStatus::Ok;
}

} // namespace bm
