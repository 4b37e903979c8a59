// Detail encoding over a base (topology-free cut and paste,
// ../shared/papers/topology-free-cut-and-paste.txt, Sec. 6.2): each vertex of a feature F finds
// its base point on the base B through the common parameterization (P^F's uv located in P^B),
// and keeps its offset from that point in the base face's frame (the paper's) or along the base's
// interpolated normal (the normal-displacement baseline).
#pragma once

#include <stdexcept>
#include <string>

#include "geobrush/canvas.hpp"
#include "geobrush/cut_paste.hpp"

namespace geobrush {

// A bad input; `port` names it ("feature" or "base").
class DetailEncodeError : public std::runtime_error {
 public:
  DetailEncodeError(std::string port, const std::string& message)
      : std::runtime_error(message), port_(std::move(port)) {}
  const std::string& port() const { return port_; }

 private:
  std::string port_;
};

// Sec. 6.2: v^BF = sum_k b_k x_k at P^F(v)'s place in P^B, d = v - v^BF, kept as
// encodeOffset's components; F.boundary[i] sits on B's vertex i with d = 0. Throws
// DetailEncodeError when the parameterizations do not match their canvases or B does not keep
// the pipeline's convention over F (cut_paste.hpp).
DetailEncoding encodeDetail(const ParameterizationPtr& feature, const ParameterizationPtr& base,
                            DetailMethod method);

// The offsets decoded over the base they were encoded on: every F vertex's position again, up to
// rounding (decodeOffset with scale 1).
std::vector<Eigen::Vector3d> decodeOverOwnBase(const DetailEncoding& encoding);

}  // namespace geobrush
