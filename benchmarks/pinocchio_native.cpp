// Native Pinocchio (C++) counterpart of `sea-sim bench`: same operations, same batch scheme.
//
// Build and run through benchmarks/native_comparison.sh, which passes the include and library
// paths of the pip package `pin` (cmeel prefix). The algorithms are function templates included
// from their .hpp files and instantiated in this translation unit, so they are compiled with this
// file's flags (-O3 -march=native -DNDEBUG). PINOCCHIO_ENABLE_TEMPLATE_INSTANTIATION is
// deliberately NOT defined: with it the headers would declare `extern template` and the calls
// would go to the generic precompiled code in libpinocchio_default.so. Only the URDF parsing
// (outside the timed code) runs in libpinocchio_parsers.so.
//
// Usage:
//   pinocchio_native --urdf PATH [--joints a,b,c] [--frame NAME] [--batches N] [--calls N]
//                    [--check]
//
// Prints one JSON object; times are microseconds per call: the median over --batches batches
// (default 31) of the mean time per call of a batch of --calls calls (default 2000), cycling
// through 64 random states (seeded, the same generator as sea-sim: joints, velocities and
// accelerations uniform in [-1, 1], base position in the [-1, 1] box, unit quaternion from a
// normalized uniform 4-vector). --check adds the results on state 0 (for cross-checking against
// Python Pinocchio).

#include <pinocchio/parsers/urdf.hpp>

#include <pinocchio/algorithm/centroidal.hpp>
#include <pinocchio/algorithm/crba.hpp>
#include <pinocchio/algorithm/frames.hpp>
#include <pinocchio/algorithm/joint-configuration.hpp>
#include <pinocchio/algorithm/kinematics.hpp>
#include <pinocchio/algorithm/model.hpp>
#include <pinocchio/algorithm/rnea.hpp>
#include <pinocchio/multibody.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <iostream>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#ifdef PINOCCHIO_ENABLE_TEMPLATE_INSTANTIATION
  #error "compile without PINOCCHIO_ENABLE_TEMPLATE_INSTANTIATION (algorithms must be instantiated here)"
#endif

namespace
{
  using Model = pinocchio::Model;
  using Data = pinocchio::Data;
  using VectorXd = Eigen::VectorXd;

  constexpr std::size_t kStates = 64;

  // Same generator as sea_ctrl::bench::Lcg (uniform in [-1, 1)).
  struct Lcg
  {
    std::uint64_t state;
    explicit Lcg(std::uint64_t seed)
    : state(seed ^ 0x9E3779B97F4A7C15ULL)
    {
    }
    double next_signed()
    {
      state = state * 6364136223846793005ULL + 1442695040888963407ULL;
      return (static_cast<double>(state >> 11) / static_cast<double>(1ULL << 53)) * 2.0 - 1.0;
    }
  };

  // Keeps the compiler from discarding or hoisting the work: everything reachable from memory
  // is considered read and written.
  inline void clobber()
  {
    asm volatile("" : : : "memory");
  }
  template<typename T>
  inline void escape(const T * p)
  {
    asm volatile("" : : "g"(p) : "memory");
  }

  double median_us(std::size_t batches, std::size_t calls, const std::function<void(std::size_t)> & f)
  {
    for (std::size_t k = 0; k < calls; ++k)
      f(k % kStates); // warm-up
    std::vector<double> means;
    means.reserve(batches);
    for (std::size_t b = 0; b < batches; ++b)
    {
      const auto start = std::chrono::steady_clock::now();
      for (std::size_t k = 0; k < calls; ++k)
        f(k % kStates);
      const auto stop = std::chrono::steady_clock::now();
      const double us = std::chrono::duration<double, std::micro>(stop - start).count();
      means.push_back(us / static_cast<double>(calls));
    }
    std::sort(means.begin(), means.end());
    return means[means.size() / 2];
  }

  std::vector<std::string> split_commas(const std::string & s)
  {
    std::vector<std::string> out;
    std::stringstream ss(s);
    std::string item;
    while (std::getline(ss, item, ','))
    {
      const auto b = item.find_first_not_of(" \t");
      const auto e = item.find_last_not_of(" \t");
      if (b != std::string::npos)
        out.push_back(item.substr(b, e - b + 1));
    }
    return out;
  }

  std::string json_string(const std::string & s)
  {
    std::string out = "\"";
    for (const char c : s)
    {
      if (c == '"' || c == '\\')
        out += '\\';
      out += c;
    }
    return out + "\"";
  }

  std::string json_number(double x)
  {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.17g", x);
    return buf;
  }

  template<typename Derived>
  std::string json_array(const Eigen::MatrixBase<Derived> & v)
  {
    std::string out = "[";
    for (Eigen::Index i = 0; i < v.size(); ++i)
      out += (i ? "," : "") + json_number(v(i));
    return out + "]";
  }

  struct Args
  {
    std::string urdf;
    std::vector<std::string> joints;
    bool reduce = false;
    std::string frame;
    std::size_t batches = 31;
    std::size_t calls = 2000;
    bool check = false;
  };

  const char * kUsage = "usage: pinocchio_native --urdf PATH [--joints a,b,c] [--frame NAME] "
                        "[--batches N] [--calls N] [--check]";

  Args parse_args(int argc, char ** argv)
  {
    Args a;
    for (int i = 1; i < argc; ++i)
    {
      const std::string arg = argv[i];
      auto value = [&]() -> std::string {
        if (i + 1 >= argc)
          throw std::invalid_argument(arg + " needs a value");
        return argv[++i];
      };
      if (arg == "--urdf")
        a.urdf = value();
      else if (arg == "--joints")
      {
        a.joints = split_commas(value());
        a.reduce = true;
      }
      else if (arg == "--frame")
        a.frame = value();
      else if (arg == "--batches")
        a.batches = std::stoul(value());
      else if (arg == "--calls")
        a.calls = std::stoul(value());
      else if (arg == "--check")
        a.check = true;
      else if (arg == "-h" || arg == "--help")
      {
        std::cout << kUsage << std::endl;
        std::exit(0);
      }
      else
        throw std::invalid_argument("unknown argument '" + arg + "'");
    }
    if (a.urdf.empty())
      throw std::invalid_argument("--urdf is required");
    if (a.batches == 0 || a.calls == 0)
      throw std::invalid_argument("--batches and --calls must be positive");
    return a;
  }

  Model load_model(const Args & args)
  {
    Model full;
    pinocchio::urdf::buildModel(args.urdf, pinocchio::JointModelFreeFlyer(), full);
    if (!args.reduce)
      return full;
    std::set<std::string> keep(args.joints.begin(), args.joints.end());
    for (const auto & name : keep)
      if (!full.existJointName(name))
        throw std::invalid_argument("--joints: no joint named '" + name + "' in " + args.urdf);
    std::vector<pinocchio::JointIndex> lock;
    // Joint 0 is the universe, joint 1 the free-flyer root; lock every other joint not kept.
    for (pinocchio::JointIndex j = 2; j < static_cast<pinocchio::JointIndex>(full.njoints); ++j)
      if (!keep.count(full.names[j]))
        lock.push_back(j);
    const VectorXd q_ref = pinocchio::neutral(full); // locked joints at 0
    return pinocchio::buildReducedModel(full, lock, q_ref);
  }
} // namespace

int main(int argc, char ** argv)
{
  Args args;
  Model model;
  try
  {
    args = parse_args(argc, argv);
    model = load_model(args);
  }
  catch (const std::exception & e)
  {
    std::cerr << "pinocchio_native: " << e.what() << "\n" << kUsage << std::endl;
    return 1;
  }

  std::string frame_name = args.frame;
  if (frame_name.empty())
    frame_name = model.existFrame("l_sole") ? "l_sole" : model.frames.back().name;
  if (!model.existFrame(frame_name))
  {
    std::cerr << "pinocchio_native: no frame named '" << frame_name << "'" << std::endl;
    return 1;
  }
  const pinocchio::FrameIndex frame = model.getFrameId(frame_name);

  // Random states, generated like sea-sim's (configurations, then velocities, then accelerations),
  // then normalized for Pinocchio's configuration space (unit quaternion).
  Lcg rng(42);
  std::vector<VectorXd> qs(kStates), vs(kStates), as(kStates);
  for (auto & q : qs)
  {
    q.resize(model.nq);
    for (Eigen::Index i = 0; i < model.nq; ++i)
      q[i] = rng.next_signed();
    pinocchio::normalize(model, q);
  }
  for (auto & v : vs)
  {
    v.resize(model.nv);
    for (Eigen::Index i = 0; i < model.nv; ++i)
      v[i] = rng.next_signed();
  }
  for (auto & a : as)
  {
    a.resize(model.nv);
    for (Eigen::Index i = 0; i < model.nv; ++i)
      a[i] = rng.next_signed();
  }
  const VectorXd a_zero = VectorXd::Zero(model.nv);

  Data data(model);
  pinocchio::Data::Matrix6x J = pinocchio::Data::Matrix6x::Zero(6, model.nv);
  pinocchio::Motion acc = pinocchio::Motion::Zero();
  const std::size_t B = args.batches, C = args.calls;

  std::vector<std::pair<std::string, double>> figures;
  figures.emplace_back("rnea_us", median_us(B, C, [&](std::size_t k) {
                         escape(pinocchio::rnea(model, data, qs[k], vs[k], as[k]).data());
                         clobber();
                       }));
  figures.emplace_back("crba_us", median_us(B, C, [&](std::size_t k) {
                         escape(pinocchio::crba(model, data, qs[k]).data());
                         clobber();
                       }));
  figures.emplace_back("centroidal_momentum_matrix_us", median_us(B, C, [&](std::size_t k) {
                         escape(pinocchio::computeCentroidalMap(model, data, qs[k]).data());
                         clobber();
                       }));
  figures.emplace_back("ccrba_us", median_us(B, C, [&](std::size_t k) {
                         escape(pinocchio::ccrba(model, data, qs[k], vs[k]).data());
                         clobber();
                       }));
  figures.emplace_back("frame_jacobian_us", median_us(B, C, [&](std::size_t k) {
                         pinocchio::computeFrameJacobian(
                           model, data, qs[k], frame, pinocchio::LOCAL_WORLD_ALIGNED, J);
                         escape(J.data());
                         clobber();
                       }));
  figures.emplace_back("frame_jacobian_dot_v_us", median_us(B, C, [&](std::size_t k) {
                         pinocchio::forwardKinematics(model, data, qs[k], vs[k], a_zero);
                         acc = pinocchio::getFrameClassicalAcceleration(
                           model, data, frame, pinocchio::LOCAL_WORLD_ALIGNED);
                         escape(&acc);
                         clobber();
                       }));

  std::string out = "{";
  out += "\"urdf\":" + json_string(args.urdf);
  out += ",\"nq\":" + std::to_string(model.nq);
  out += ",\"nv\":" + std::to_string(model.nv);
  out += ",\"frame\":" + json_string(frame_name);
  out += ",\"batches\":" + std::to_string(B);
  out += ",\"calls\":" + std::to_string(C);
  out += ",\"states\":" + std::to_string(kStates);
  out += ",\"pinocchio_version\":" + json_string(PINOCCHIO_VERSION);
  out += ",\"eigen_version\":"
         + json_string(
           std::to_string(EIGEN_WORLD_VERSION) + "." + std::to_string(EIGEN_MAJOR_VERSION) + "."
           + std::to_string(EIGEN_MINOR_VERSION));
  out += ",\"eigen_max_align_bytes\":" + std::to_string(EIGEN_MAX_ALIGN_BYTES);
  out += ",\"simd\":" + json_string(Eigen::SimdInstructionSetsInUse());
  for (const auto & f : figures)
    out += "," + json_string(f.first) + ":" + json_number(f.second);
  out += ",\"notes\":{"
         "\"crba_us\":\"pinocchio::crba (LOCAL convention) fills only the upper triangle of M\","
         "\"centroidal_momentum_matrix_us\":\"pinocchio::computeCentroidalMap(q) (Ag only)\","
         "\"ccrba_us\":\"pinocchio::ccrba(q, v): Ag plus centroidal momentum and inertia\","
         "\"frame_jacobian_us\":\"computeFrameJacobian(q, frame, LOCAL_WORLD_ALIGNED), "
         "forward kinematics included\","
         "\"frame_jacobian_dot_v_us\":\"forwardKinematics(q, v, 0) + "
         "getFrameClassicalAcceleration(frame, LOCAL_WORLD_ALIGNED)\"}";

  if (args.check)
  {
    // Results on state 0, for cross-checking against Python Pinocchio.
    const VectorXd & q = qs[0];
    const VectorXd & v = vs[0];
    const VectorXd & a = as[0];
    out += ",\"check\":{\"q\":" + json_array(q) + ",\"v\":" + json_array(v)
           + ",\"a\":" + json_array(a);
    out += ",\"rnea\":" + json_array(pinocchio::rnea(model, data, q, v, a));
    Eigen::MatrixXd M = pinocchio::crba(model, data, q);
    M.triangularView<Eigen::StrictlyLower>() = M.transpose().triangularView<Eigen::StrictlyLower>();
    out += ",\"crba_row0\":" + json_array(M.row(0).transpose());
    out += ",\"crba_diag\":" + json_array(M.diagonal());
    const pinocchio::Data::Matrix6x Ag = pinocchio::computeCentroidalMap(model, data, q);
    out += ",\"ag_v\":" + json_array(Ag * v);
    J.setZero();
    pinocchio::computeFrameJacobian(model, data, q, frame, pinocchio::LOCAL_WORLD_ALIGNED, J);
    out += ",\"j_v\":" + json_array(J * v);
    pinocchio::forwardKinematics(model, data, q, v, a_zero);
    out += ",\"jdot_v\":"
           + json_array(pinocchio::getFrameClassicalAcceleration(
                          model, data, frame, pinocchio::LOCAL_WORLD_ALIGNED)
                          .toVector());
    out += "}";
  }
  out += "}";
  std::cout << out << std::endl;
  return 0;
}
