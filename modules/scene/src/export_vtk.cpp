// The VTK exporter: VTK stays inside this file (the scene's public headers carry no VTK type).
#include <system_error>

#include <fmt/format.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkFloatArray.h>
#include <vtkImageData.h>
#include <vtkInformation.h>
#include <vtkMultiBlockDataSet.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkTypeUInt64Array.h>
#include <vtkUnsignedShortArray.h>
#include <vtkXMLImageDataWriter.h>
#include <vtkXMLMultiBlockDataWriter.h>

#include "trainsim/core/error.hpp"
#include "trainsim/scene/export.hpp"

namespace trainsim::scene {
namespace {

vtkNew<vtkPolyData> tilePolyData(const Tile& tile, const Eigen::Vector3d& origin) {
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  vtkNew<vtkCellArray> polys, lines;
  vtkNew<vtkUnsignedShortArray> cls, material;
  vtkNew<vtkTypeUInt64Array> instance;
  vtkNew<vtkFloatArray> radius;
  cls->SetName("class");
  material->SetName("material");
  instance->SetName("instance");
  radius->SetName("radius_m");
  // vtkPolyData orders cells verts, lines, polys, strips: the wires' values go first.
  vtkNew<vtkUnsignedShortArray> wire_cls, wire_material;
  vtkNew<vtkTypeUInt64Array> wire_instance;
  vtkNew<vtkFloatArray> wire_radius;
  for (const Wire& wire : tile.wires) {
    const vtkIdType base = points->GetNumberOfPoints();
    for (const auto& p : wire.points) {
      const Eigen::Vector3d w = tile.origin + p.cast<double>() - origin;
      points->InsertNextPoint(w.x(), w.y(), w.z());
    }
    lines->InsertNextCell(static_cast<vtkIdType>(wire.points.size()));
    for (std::size_t k = 0; k < wire.points.size(); ++k)
      lines->InsertCellPoint(base + static_cast<vtkIdType>(k));
    wire_cls->InsertNextValue(wire.cls);
    wire_material->InsertNextValue(wire.material);
    wire_instance->InsertNextValue(wire.instance);
    wire_radius->InsertNextValue(wire.radius_m);
  }
  for (const Object& object : tile.objects) {
    const Mesh& mesh = *object.mesh;
    const vtkIdType base = points->GetNumberOfPoints();
    const Eigen::Vector3d shift = object.position - origin;
    const Eigen::Matrix3d linear = object.linear.cast<double>();
    for (const auto& v : mesh.vertices) {
      const Eigen::Vector3d w = shift + linear * v.cast<double>();
      points->InsertNextPoint(w.x(), w.y(), w.z());
    }
    for (const MeshPart& part : mesh.parts)
      for (std::uint32_t t = part.first_triangle; t < part.first_triangle + part.triangle_count;
           ++t) {
        const auto& tri = mesh.triangles[t];
        const vtkIdType ids[3] = {base + tri[0], base + tri[1], base + tri[2]};
        polys->InsertNextCell(3, ids);
        cls->InsertNextValue(part.cls);
        material->InsertNextValue(part.material);
        instance->InsertNextValue(object.instance);
        radius->InsertNextValue(0.0f);
      }
  }
  // Cell data in vtkPolyData's cell order: lines first, then polygons.
  for (vtkIdType k = 0; k < cls->GetNumberOfValues(); ++k) {
    wire_cls->InsertNextValue(cls->GetValue(k));
    wire_material->InsertNextValue(material->GetValue(k));
    wire_instance->InsertNextValue(instance->GetValue(k));
    wire_radius->InsertNextValue(radius->GetValue(k));
  }
  wire_cls->SetName("class");
  wire_material->SetName("material");
  wire_instance->SetName("instance");
  wire_radius->SetName("radius_m");
  vtkNew<vtkPolyData> data;
  data->SetPoints(points);
  data->SetLines(lines);
  data->SetPolys(polys);
  data->GetCellData()->AddArray(wire_cls);
  data->GetCellData()->AddArray(wire_material);
  data->GetCellData()->AddArray(wire_instance);
  data->GetCellData()->AddArray(wire_radius);
  data->GetCellData()->SetActiveScalars("class");
  vtkNew<vtkDoubleArray> origin_array;
  origin_array->SetName("origin_m");
  origin_array->SetNumberOfComponents(3);
  origin_array->InsertNextTuple3(origin.x(), origin.y(), origin.z());
  data->GetFieldData()->AddArray(origin_array);
  return data;
}

}  // namespace

void writeVtm(std::span<const std::shared_ptr<const Tile>> tiles, const std::filesystem::path& vtm,
              const Eigen::Vector3d& origin) {
  namespace fs = std::filesystem;
  const fs::path folder = vtm.parent_path().empty() ? fs::path(".") : vtm.parent_path();
  const std::string stem = vtm.stem().string();
  const fs::path staging = folder / ("." + stem + ".partial");
  std::error_code ec;
  fs::remove_all(staging, ec);
  fs::create_directories(staging, ec);
  if (ec)
    throw IoError(
        fmt::format("{}: cannot create {}: {}", vtm.string(), staging.string(), ec.message()));

  vtkNew<vtkMultiBlockDataSet> blocks;
  blocks->SetNumberOfBlocks(static_cast<unsigned>(tiles.size()));
  for (std::size_t k = 0; k < tiles.size(); ++k) {
    auto data = tilePolyData(*tiles[k], origin);
    blocks->SetBlock(static_cast<unsigned>(k), data);
    blocks->GetMetaData(static_cast<unsigned>(k))
        ->Set(vtkMultiBlockDataSet::NAME(),
              fmt::format("tile_{}_{}", tiles[k]->index.i, tiles[k]->index.j).c_str());
  }
  vtkNew<vtkXMLMultiBlockDataWriter> writer;
  writer->SetFileName((staging / (stem + ".vtm")).string().c_str());
  writer->SetInputData(blocks);
  writer->SetDataModeToAppended();
  writer->SetCompressorTypeToZLib();
  if (writer->Write() != 1) {
    fs::remove_all(staging, ec);
    throw IoError(fmt::format("{}: VTK could not write the scene", vtm.string()));
  }
  // Into place: the data folder first, then the .vtm that names it.
  fs::remove_all(folder / stem, ec);
  if (fs::exists(staging / stem))
    fs::rename(staging / stem, folder / stem, ec);
  if (!ec)
    fs::rename(staging / (stem + ".vtm"), vtm, ec);
  std::error_code ignored;
  fs::remove_all(staging, ignored);
  if (ec)
    throw IoError(
        fmt::format("{}: cannot move the scene into place: {}", vtm.string(), ec.message()));
}

void writeHeightVti(const std::filesystem::path& vti, int n, const Eigen::Vector2d& origin,
                    double spacing_m, std::span<const double> heights) {
  namespace fs = std::filesystem;
  vtkNew<vtkImageData> image;
  image->SetDimensions(n, n, 1);
  image->SetOrigin(origin.x(), origin.y(), 0.0);
  image->SetSpacing(spacing_m, spacing_m, 1.0);
  vtkNew<vtkDoubleArray> height;
  height->SetName("height_m");
  height->SetNumberOfValues(static_cast<vtkIdType>(heights.size()));
  for (std::size_t i = 0; i < heights.size(); ++i)
    height->SetValue(static_cast<vtkIdType>(i), heights[i]);
  image->GetPointData()->SetScalars(height);
  const fs::path temp = vti.parent_path() / ("." + vti.filename().string() + ".partial");
  vtkNew<vtkXMLImageDataWriter> writer;
  writer->SetFileName(temp.string().c_str());
  writer->SetInputData(image);
  writer->SetDataModeToAppended();
  writer->SetCompressorTypeToZLib();
  std::error_code ec;
  if (writer->Write() != 1) {
    fs::remove(temp, ec);
    throw IoError(fmt::format("{}: VTK could not write the height grid", vti.string()));
  }
  fs::rename(temp, vti, ec);
  if (ec)
    throw IoError(fmt::format("{}: cannot move it into place: {}", vti.string(), ec.message()));
}

}  // namespace trainsim::scene
