// Binary little-endian PLY writer and a reader for the vertex element (docs/formats.md).
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <sstream>

#include "ramtk/core/error.h"
#include "ramtk/core/file_io.h"
#include "ramtk/vision/stereo/point_cloud.h"

namespace ramtk::vision {
namespace {

static_assert(sizeof(float) == 4, "PLY float32 needs a 4-byte float");

bool HostIsLittleEndian() {
  const std::uint16_t one = 1;
  unsigned char b = 0;
  std::memcpy(&b, &one, 1);
  return b == 1;
}

// Size in bytes of a PLY scalar type, 0 if unknown.
int TypeSize(const std::string& t) {
  if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
  if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
  if (t == "int" || t == "uint" || t == "int32" || t == "uint32" || t == "float" || t == "float32") return 4;
  if (t == "double" || t == "float64") return 8;
  return 0;
}

double ReadScalarLe(const unsigned char* p, const std::string& t) {
  unsigned char b[8];
  const int n = TypeSize(t);
  std::memcpy(b, p, n);
  if (!HostIsLittleEndian())
    for (int i = 0; i < n / 2; ++i) std::swap(b[i], b[n - 1 - i]);
  if (t == "char" || t == "int8") return static_cast<double>(static_cast<std::int8_t>(b[0]));
  if (t == "uchar" || t == "uint8") return b[0];
  if (t == "short" || t == "int16") {
    std::int16_t v;
    std::memcpy(&v, b, 2);
    return v;
  }
  if (t == "ushort" || t == "uint16") {
    std::uint16_t v;
    std::memcpy(&v, b, 2);
    return v;
  }
  if (t == "int" || t == "int32") {
    std::int32_t v;
    std::memcpy(&v, b, 4);
    return v;
  }
  if (t == "uint" || t == "uint32") {
    std::uint32_t v;
    std::memcpy(&v, b, 4);
    return v;
  }
  if (t == "float" || t == "float32") {
    float v;
    std::memcpy(&v, b, 4);
    return v;
  }
  double v;
  std::memcpy(&v, b, 8);
  return v;
}

struct PlyProperty {
  std::string type, name;
};
struct PlyElement {
  std::string name;
  long count = 0;
  std::vector<PlyProperty> properties;
  bool has_list = false;
};

}  // namespace

void PointCloud::Check(const std::string& where) const {
  if (!sigma_mm.empty() && sigma_mm.size() != points_in_left.size())
    throw InputError({where, 0, "sigma"}, "has " + std::to_string(sigma_mm.size()) + " values for " +
                                              std::to_string(points_in_left.size()) + " points");
  if (!quality.empty() && quality.size() != points_in_left.size())
    throw InputError({where, 0, "quality"}, "has " + std::to_string(quality.size()) + " values for " +
                                                std::to_string(points_in_left.size()) + " points");
}

namespace {

std::string PlyHeader(const PointCloud& cloud, const std::string& comment) {
  std::ostringstream h;
  h << "ply\nformat binary_little_endian 1.0\n";
  h << "comment ramtk point cloud: x y z in mm in the left-camera frame";
  if (!cloud.sigma_mm.empty()) h << "; sigma = point std dev along its ray, mm";
  h << "\n";
  if (!comment.empty()) {
    std::istringstream lines(comment);
    for (std::string line; std::getline(lines, line);) h << "comment " << line << "\n";
  }
  h << "element vertex " << cloud.size() << "\n";
  h << "property float x\nproperty float y\nproperty float z\n";
  if (!cloud.sigma_mm.empty()) h << "property float sigma\n";
  if (!cloud.quality.empty()) h << "property float quality\n";
  h << "end_header\n";
  return h.str();
}

std::size_t VertexBytes(const PointCloud& cloud) {
  return 4 * static_cast<std::size_t>(3 + (cloud.sigma_mm.empty() ? 0 : 1) + (cloud.quality.empty() ? 0 : 1));
}

// The body bytes of vertices [begin, end) into `base`. Each vertex has its own bytes: blocks of
// vertices in parallel (a thesis frame's 6.4 M vertices took ~0.2 s appended one float at a time).
void FillVertices(const PointCloud& cloud, std::size_t begin, std::size_t end, char* base) {
  const std::size_t stride = VertexBytes(cloud);
  const bool swap = !HostIsLittleEndian();
  auto put = [swap](char* at, float value) {
    std::memcpy(at, &value, 4);
    if (swap) std::swap(at[0], at[3]), std::swap(at[1], at[2]);
  };
  tbb::parallel_for(tbb::blocked_range<std::size_t>(begin, end, 1 << 14),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t i = r.begin(); i < r.end(); ++i) {
                        char* at = base + (i - begin) * stride;
                        for (int k = 0; k < 3; ++k, at += 4) put(at, cloud.points_in_left[i][k]);
                        if (!cloud.sigma_mm.empty()) put(at, cloud.sigma_mm[i]), at += 4;
                        if (!cloud.quality.empty()) put(at, cloud.quality[i]);
                      }
                    });
}

}  // namespace

std::string PlyBytes(const PointCloud& cloud, const std::string& comment) {
  cloud.Check();
  std::string out = PlyHeader(cloud, comment);
  const std::size_t header = out.size();
  out.resize(header + cloud.size() * VertexBytes(cloud));
  FillVertices(cloud, 0, cloud.size(), out.data() + header);
  return out;
}

void WritePly(const std::string& path, const PointCloud& cloud, const std::string& comment) {
  cloud.Check(path);
  // Streamed in blocks of vertices through one reused buffer: the body of a thesis frame's cloud
  // is 128 MB, which as one string cost its page faults besides the copy (docs/performance.md).
  WriteFileAtomically(path, [&](std::ostream& out) {
    out << PlyHeader(cloud, comment);
    constexpr std::size_t kBlock = 1 << 18;
    std::vector<char> buffer(std::min(cloud.size(), kBlock) * VertexBytes(cloud));
    for (std::size_t begin = 0; begin < cloud.size(); begin += kBlock) {
      const std::size_t end = std::min(cloud.size(), begin + kBlock);
      FillVertices(cloud, begin, end, buffer.data());
      out.write(buffer.data(), static_cast<std::streamsize>((end - begin) * VertexBytes(cloud)));
    }
  });
}

PointCloud ReadPly(const std::string& path) {
  const std::string data = ReadTextFile(path);
  std::size_t pos = 0;
  int line_no = 0;
  auto next_line = [&](std::string* line) {
    const std::size_t end = data.find('\n', pos);
    if (end == std::string::npos) throw InputError({path, line_no + 1, "header"}, "header ends before end_header");
    *line = data.substr(pos, end - pos);
    if (!line->empty() && line->back() == '\r') line->pop_back();
    pos = end + 1;
    ++line_no;
  };
  std::string line;
  next_line(&line);
  if (line != "ply") throw InputError({path, 1, "header"}, "not a PLY file (first line is not 'ply')");
  std::string format;
  std::vector<PlyElement> elements;
  for (;;) {
    next_line(&line);
    std::istringstream ss(line);
    std::string key;
    ss >> key;
    if (key == "end_header") break;
    if (key == "comment" || key == "obj_info" || key.empty()) continue;
    if (key == "format") {
      ss >> format;
      if (format != "binary_little_endian" && format != "ascii")
        throw InputError({path, line_no, "format"}, "unsupported PLY format '" + format + "'");
    } else if (key == "element") {
      PlyElement e;
      if (!(ss >> e.name >> e.count) || e.count < 0)
        throw InputError({path, line_no, "element"}, "cannot read '" + line + "'");
      elements.push_back(e);
    } else if (key == "property") {
      if (elements.empty()) throw InputError({path, line_no, "property"}, "property before any element");
      PlyProperty p;
      ss >> p.type;
      if (p.type == "list") {
        elements.back().has_list = true;
        std::string count_type, item_type;
        ss >> count_type >> item_type >> p.name;
      } else {
        ss >> p.name;
        if (TypeSize(p.type) == 0)
          throw InputError({path, line_no, "property " + p.name}, "unknown type '" + p.type + "'");
      }
      elements.back().properties.push_back(p);
    } else {
      throw InputError({path, line_no, "header"}, "unexpected header line '" + line + "'");
    }
  }
  if (format.empty()) throw InputError({path, 0, "format"}, "the header has no format line");
  PointCloud cloud;
  bool found = false;
  for (const PlyElement& e : elements) {
    if (e.name != "vertex") {
      if (e.count == 0) continue;
      if (e.has_list || format == "ascii")
        throw InputError({path, 0, "element " + e.name},
                         "elements with lists (or ASCII elements) before 'vertex' are not supported");
      std::size_t stride = 0;
      for (const PlyProperty& p : e.properties) stride += TypeSize(p.type);
      pos += stride * static_cast<std::size_t>(e.count);
      continue;
    }
    if (e.has_list) throw InputError({path, 0, "element vertex"}, "list properties in 'vertex' are not supported");
    int ix = -1, iy = -1, iz = -1, is = -1, iq = -1;
    std::vector<std::size_t> offset;
    std::size_t stride = 0;
    for (std::size_t k = 0; k < e.properties.size(); ++k) {
      const std::string& n = e.properties[k].name;
      const int kk = static_cast<int>(k);
      if (n == "x") ix = kk;
      if (n == "y") iy = kk;
      if (n == "z") iz = kk;
      if (n == "sigma") is = kk;
      if (n == "quality") iq = kk;
      offset.push_back(stride);
      stride += TypeSize(e.properties[k].type);
    }
    if (ix < 0 || iy < 0 || iz < 0) throw InputError({path, 0, "element vertex"}, "needs properties x, y and z");
    const std::size_t n = static_cast<std::size_t>(e.count);
    cloud.points_in_left.resize(n);
    if (is >= 0) cloud.sigma_mm.resize(n);
    if (iq >= 0) cloud.quality.resize(n);
    if (format == "binary_little_endian") {
      if (data.size() < pos + stride * n)
        throw InputError({path, 0, "element vertex"}, "file ends after " +
                                                          std::to_string((data.size() - pos) / stride) + " of " +
                                                          std::to_string(n) + " vertices");
      const auto* base = reinterpret_cast<const unsigned char*>(data.data()) + pos;
      auto get = [&](std::size_t i, int k) {
        return ReadScalarLe(base + i * stride + offset[k], e.properties[k].type);
      };
      for (std::size_t i = 0; i < n; ++i) {
        cloud.points_in_left[i] = Eigen::Vector3f(get(i, ix), get(i, iy), get(i, iz));
        if (is >= 0) cloud.sigma_mm[i] = static_cast<float>(get(i, is));
        if (iq >= 0) cloud.quality[i] = static_cast<float>(get(i, iq));
      }
    } else {
      std::istringstream body(data.substr(pos));
      std::vector<double> v(e.properties.size());
      for (std::size_t i = 0; i < n; ++i) {
        for (double& x : v)
          if (!(body >> x))
            throw InputError({path, line_no + static_cast<int>(i) + 1, "element vertex"},
                             "cannot read vertex " + std::to_string(i));
        cloud.points_in_left[i] = Eigen::Vector3f(v[ix], v[iy], v[iz]);
        if (is >= 0) cloud.sigma_mm[i] = static_cast<float>(v[is]);
        if (iq >= 0) cloud.quality[i] = static_cast<float>(v[iq]);
      }
    }
    found = true;
    break;
  }
  if (!found) throw InputError({path, 0, "element vertex"}, "the file has no vertex element");
  return cloud;
}

}  // namespace ramtk::vision
