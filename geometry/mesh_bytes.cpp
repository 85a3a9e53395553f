#include "geometry/mesh_bytes.h"

#include "core/error.h"

#include <cstdint>
#include <cstring>

namespace hipfai::geometry {

namespace {

template <typename T>
void put(std::string& out, const T& value) {
  out.append(reinterpret_cast<const char*>(&value), sizeof(T));
}

// (An empty vector's data() may be null, and memcpy's pointers must never be: nothing to copy.)
void put_bytes(std::string& out, const void* data, std::size_t size) {
  if (size > 0) out.append(static_cast<const char*>(data), size);
}

void take_bytes(std::string_view& in, void* data, std::size_t size, const std::string& what) {
  if (in.size() < size) throw_error(what, ": truncated mesh bytes");
  if (size == 0) return;
  std::memcpy(data, in.data(), size);
  in.remove_prefix(size);
}

// A count of items of `item_size` bytes each that `in` can still hold.
std::uint64_t take_count(std::string_view& in, std::size_t item_size, const std::string& what) {
  std::uint64_t count = 0;
  take_bytes(in, &count, sizeof count, what);
  if (item_size > 0 && count > in.size() / item_size) throw_error(what, ": truncated mesh bytes");
  return count;
}

}  // namespace

void append_mesh_bytes(std::string& out, const TriMesh& mesh) {
  put(out, static_cast<std::uint64_t>(mesh.vertices.size()));
  for (const Vec3& v : mesh.vertices) put_bytes(out, v.data(), 3 * sizeof(double));
  put(out, static_cast<std::uint64_t>(mesh.triangles.size()));
  put_bytes(out, mesh.triangles.data(), mesh.triangles.size() * sizeof(Triangle));
  put(out, static_cast<std::uint64_t>(mesh.vertex_fields.size()));
  for (const auto& [name, values] : mesh.vertex_fields) {
    put(out, static_cast<std::uint64_t>(name.size()));
    out += name;
    put(out, static_cast<std::uint64_t>(values.size()));
    put_bytes(out, values.data(), values.size() * sizeof(double));
  }
}

TriMesh read_mesh_bytes(std::string_view& in, const std::string& what) {
  TriMesh mesh;
  mesh.vertices.resize(take_count(in, 3 * sizeof(double), what));
  for (Vec3& v : mesh.vertices) take_bytes(in, v.data(), 3 * sizeof(double), what);
  mesh.triangles.resize(take_count(in, sizeof(Triangle), what));
  take_bytes(in, mesh.triangles.data(), mesh.triangles.size() * sizeof(Triangle), what);
  for (const Triangle& t : mesh.triangles) {
    for (const std::int32_t index : t) {
      if (index < 0 || static_cast<std::size_t>(index) >= mesh.vertices.size()) {
        throw_error(what, ": triangle vertex index ", index, " for ", mesh.vertices.size(), " vertices");
      }
    }
  }
  const std::uint64_t fields = take_count(in, 2 * sizeof(std::uint64_t), what);
  for (std::uint64_t f = 0; f < fields; ++f) {
    std::string name(take_count(in, 1, what), '\0');
    take_bytes(in, name.data(), name.size(), what);
    std::vector<double> values(take_count(in, sizeof(double), what));
    take_bytes(in, values.data(), values.size() * sizeof(double), what);
    if (values.size() != mesh.vertices.size()) {
      throw_error(what, ": vertex field '", name, "' has ", values.size(), " values for ", mesh.vertices.size(),
                  " vertices");
    }
    mesh.vertex_fields.emplace(std::move(name), std::move(values));
  }
  return mesh;
}

}  // namespace hipfai::geometry
