#include "bmScriptedDevice.h"

#include <algorithm>
#include <cctype>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <Eigen/Geometry>

namespace bm {

const char* ToString(ScriptMode m) {
  switch (m) {
  case ScriptMode::Feed:
    return "feed";
  case ScriptMode::Force:
    return "force";
  case ScriptMode::Trajectory:
    return "trajectory";
  }
  return "?";
}

std::vector<TrajectorySample> LoadTrajectoryCsv(const std::string& path) {
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
    std::vector<double> v;
    std::stringstream ss(line);
    std::string cell;
    while (std::getline(ss, cell, ',')) {
      try {
        v.push_back(std::stod(cell));
      } catch (const std::exception&) {
        throw std::runtime_error(path + ":" + std::to_string(lineNo) + ": not a number: '" + cell +
                                 "'");
      }
    }
    if (v.size() != 4 && v.size() != 8)
      throw std::runtime_error(path + ":" + std::to_string(lineNo) + ": needs 4 or 8 columns");
    TrajectorySample s;
    s.timeS = v[0];
    s.positionMm = {v[1], v[2], v[3]};
    if (v.size() == 8)
      s.rotation = Eigen::Quaterniond(v[4], v[5], v[6], v[7]).normalized().toRotationMatrix();
    if (!out.empty() && !(s.timeS > out.back().timeS))
      throw std::runtime_error(path + ":" + std::to_string(lineNo) + ": times must increase");
    out.push_back(s);
  }
  if (out.empty())
    throw std::runtime_error("trajectory '" + path + "' has no samples");
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

void ScriptedDevice::Advance(double timeS, double dtS) {
  if (O_.mode == ScriptMode::Force) {
    // Semi-implicit Euler: m dv/dt = F_applied + F_device - c v (N, kg, mm/s: 1 N/kg = 1000
    // mm/s^2).
    const Eigen::Vector3d f = -O_.axis * O_.appliedForceN + Force_;
    const double m = O_.massKg, c = O_.dampingNsPerMm * 1000.0; // N s/m
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
