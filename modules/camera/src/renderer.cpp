#include "trainsim/camera/renderer.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>

#include <vtkActor.h>
#include <vtkAutoInit.h>
#include <vtkCallbackCommand.h>
#include <vtkCamera.h>
#include <vtkCommand.h>
#include <vtkFloatArray.h>
#include <vtkLight.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkOpenGLRenderWindow.h>
#include <vtkOpenGLShaderProperty.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkPropCollection.h>
#include <vtkProperty.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkSmartPointer.h>
#include <vtkTextureObject.h>
#include <vtkUnsignedCharArray.h>

#include "frustum.hpp"
#include "level_of_detail.hpp"
#include "render_thread.hpp"
#include "shade_shader.hpp"
#include "trainsim/core/error.hpp"
#include "vtk_meshes.hpp"

VTK_MODULE_INIT(vtkRenderingOpenGL2);

namespace trainsim::camera {
namespace {

// One level of a shared mesh as VTK polydata (float vertices relative to the mesh's origin),
// with its triangles' surface colours ("albedo") and classes ("class"). A mesh with emitting
// parts (a signal's lit lamp) is drawn in the colour pass as two: what reflects, lit by the
// scene's lights, and what emits, at its emission colour whatever the lighting.
struct MeshLevel {
  vtkSmartPointer<vtkPolyData> poly;          // every triangle (the id pass's)
  vtkSmartPointer<vtkPolyData> lit, glow;     // when some part emits: the two halves; else null
  vtkSmartPointer<vtkPolyDataMapper> mapper;  // the colour pass's, shared by the objects
  vtkSmartPointer<vtkPolyDataMapper> glow_mapper;  // the same for what emits
  std::int64_t triangles = 0;
};

struct MeshEntry {
  std::shared_ptr<const scene::Mesh> mesh;  // keeps the key's pointer valid
  std::array<MeshLevel, kLevels> levels;    // made as they are first needed
  std::uint64_t used = 0;
};

// An object (or a wire) as drawn: its actors for the two passes at each level of detail it has
// been drawn at (and for what of it emits light, if anything), and its id slot.
struct DrawnEntry {
  std::shared_ptr<const scene::Tile> tile;  // the tile it was made from, kept alive; null: unmade
  std::array<vtkSmartPointer<vtkActor>, kLevels> colour, id, glow;
  bool shares_colour_mapper = false;  // an object's colour actors draw its mesh's mappers
  int shade = -1;  // whether its box may be out of full daylight (RendererOptions::shade_meets)
  std::uint32_t slot = 0;
  int level = 0;  // this render's
  std::int64_t triangles = 0;
  std::uint64_t used = 0;
  vtkActor* colourActor() const { return colour[level]; }
  vtkActor* idActor() const { return id[level]; }
  vtkActor* glowActor() const { return glow[level]; }  // null when nothing of it emits
};

// Places a drawn thing's actors (one matrix shared by the passes).
void place(DrawnEntry& e, const Eigen::Matrix3d& linear, const Eigen::Vector3d& translation) {
  vtkNew<vtkMatrix4x4> m;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c)
      m->SetElement(r, c, linear(r, c));
    m->SetElement(r, 3, translation[r]);
  }
  e.colourActor()->SetUserMatrix(m);
  e.idActor()->SetUserMatrix(m);
  if (vtkActor* glow = e.glowActor())
    glow->SetUserMatrix(m);
}

// Slot s is drawn as object s + 1 (0: nothing).
void noteInstance(CameraImages& out, std::uint32_t slot, scene::InstanceId instance) {
  if (out.instances.size() < slot + 2)
    out.instances.resize(slot + 2, 0);
  out.instances[slot + 1] = instance;
}

scene::Box3d wireBounds(const scene::Tile& tile, const scene::Wire& wire) {
  scene::Box3d b;
  for (const Eigen::Vector3f& p : wire.points)
    b.extend(tile.origin + p.cast<double>());
  b.min.array() -= wire.radius_m;
  b.max.array() += wire.radius_m;
  return b;
}

}  // namespace

// The VTK side: made, used and destroyed on the render thread only.
struct Renderer::Impl {
  struct Gl {
    vtkNew<vtkRenderWindow> window;
    vtkNew<vtkRenderer> renderer;
    // The colour pass's lights: the day's sun and lamps, then the shade's where some pixel
    // shows a surface out of full daylight (setLights()); as many as a render has asked for.
    std::vector<vtkSmartPointer<vtkLight>> lights;
    std::size_t lights_on = 0;
    int day_lights = -1;  // what the lit shader's replacements were written for
    // The colour pass's, the id pass's, and the colour pass's for what emits light and for
    // wires (see actor() and render()).
    vtkNew<vtkProperty> lit, unlit, glow, wire;
    // The colour pass's shader replacements and their inputs, for surfaces and wires (see
    // shade_shader.hpp), and each pixel's share of daylight.
    vtkNew<vtkOpenGLShaderProperty> lit_shader, wire_shader;
    ShadeInputs lit_inputs, wire_inputs;
    vtkNew<vtkCallbackCommand> lit_uniforms, wire_uniforms;
    vtkNew<vtkTextureObject> shares;
    std::map<const scene::Mesh*, MeshEntry> meshes;
    // Drawn things by (tile, index in the tile; wires after the objects).
    std::map<std::pair<scene::TileIndex, std::uint32_t>, DrawnEntry> drawn;
    std::vector<std::uint32_t> free_slots;
    std::uint32_t next_slot = 0;
    std::uint64_t frame = 0;
  };

  std::shared_ptr<RenderThread> thread = RenderThread::shared();
  std::unique_ptr<Gl> gl;

  ~Impl() {
    thread->run([this] {
      gl.reset();
      return 0;
    });
  }

  // Entries not drawn in this many renders are dropped (a thing that leaves the view for a
  // moment keeps its actors; memory follows what is in view, not the route).
  static constexpr std::uint64_t kKeepRenders = 4;

  void start(const RendererOptions& o) {
    gl = std::make_unique<Gl>();
    vtkRenderWindow* w = gl->window;
    w->SetOffScreenRendering(1);
    w->SetMultiSamples(0);  // no blended ids, and the depth buffer reads back directly
    w->SetSize(o.intrinsics.width, o.intrinsics.height);
    w->AddRenderer(gl->renderer);
    gl->renderer->AutomaticLightCreationOff();
    for (vtkProperty* p : {gl->lit.Get(), gl->unlit.Get(), gl->glow.Get(), gl->wire.Get()}) {
      p->SetInterpolationToFlat();
      p->SetSpecular(0.0);
    }
    // The lit surfaces' and the wires' ambient and diffuse come from the shader's inputs
    // (ShadeInputs), set per render: the properties never change, so their mappers keep
    // their buffers.
    gl->lit->SetAmbient(1.0);
    gl->lit->SetDiffuse(1.0);
    gl->unlit->LightingOff();  // the id pass: the colour exactly as given
    gl->glow->LightingOff();   // a lamp: its emission colour whatever the lights
    gl->wire->LightingOff();   // shaded by one factor per render (light())
    gl->wire->SetAmbient(1.0);
    gl->wire->SetDiffuse(0.0);
    setShadeShader(gl->wire_shader, false, 0);
    gl->lit_uniforms->SetCallback(setShadeUniforms);
    gl->lit_uniforms->SetClientData(&gl->lit_inputs);
    gl->wire_uniforms->SetCallback(setShadeUniforms);
    gl->wire_uniforms->SetClientData(&gl->wire_inputs);
    vtkCamera* cam = gl->renderer->GetActiveCamera();
    cam->SetPosition(0.0, 0.0, 0.0);
    cam->SetClippingRange(o.near_m, o.far_m);
    vtkNew<vtkMatrix4x4> projection;
    const Eigen::Matrix4d P = o.intrinsics.glProjection(o.near_m, o.far_m);
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c)
        projection->SetElement(r, c, P(r, c));
    cam->SetExplicitProjectionTransformMatrix(projection);
    cam->UseExplicitProjectionTransformMatrixOn();
    w->Render();  // nothing yet: the OpenGL context, which the shares' texture needs
    gl->shares->SetContext(vtkOpenGLRenderWindow::SafeDownCast(w));
  }

  static MeshLevel meshLevel(const scene::Mesh& mesh) {
    MeshLevel m;
    m.poly = meshPolyData(mesh);
    m.triangles = static_cast<std::int64_t>(mesh.triangles.size());
    if (anyEmits(mesh)) {
      m.lit = meshPolyData(mesh, Emitting::kNot);
      m.glow = meshPolyData(mesh, Emitting::kOnly);
    }
    return m;
  }

  // The mesh's entry with `level` made; a level that would not save a fifth of the triangles of
  // the one before is that one.
  MeshEntry& meshEntry(const std::shared_ptr<const scene::Mesh>& mesh, int level) {
    MeshEntry& e = gl->meshes[mesh.get()];
    if (!e.levels[0].poly) {
      e.mesh = mesh;
      e.levels[0] = meshLevel(*mesh);
    }
    for (int l = 1; l <= level; ++l) {
      MeshLevel& m = e.levels[l];
      if (m.poly)
        continue;
      const MeshLevel& before = e.levels[l - 1];
      const scene::Mesh light = clustered(*mesh, cellSize(l));
      const auto n = static_cast<std::int64_t>(light.triangles.size());
      // A mesh that collapses altogether (smaller than a cell) keeps its last level: it spans
      // about a pixel, and the semantic image should still show it.
      if (n > 0 && n * 5 <= before.triangles * 4)
        m = meshLevel(light);
      else
        m = before;
    }
    MeshLevel& m = e.levels[level];
    if (!m.mapper) {
      m.mapper = colourMapper(m.lit ? m.lit : m.poly, "albedo");
      m.mapper->AddObserver(vtkCommand::UpdateShaderEvent, gl->lit_uniforms);
    }
    if (m.glow && !m.glow_mapper)
      m.glow_mapper = colourMapper(m.glow, "albedo");
    e.used = gl->frame;
    return e;
  }

  std::uint32_t takeSlot() {
    if (!gl->free_slots.empty()) {
      const std::uint32_t s = gl->free_slots.back();
      gl->free_slots.pop_back();
      return s;
    }
    if (gl->next_slot >= kSlots)
      throw RuntimeError("camera: more than 65535 objects in view at once");
    return gl->next_slot++;
  }
  static constexpr std::uint32_t kSlots = 0xFFFF;

  // A mapper rebuilds its vertex and index buffers whenever the property of the actor it draws
  // is another one, or was modified (vtkOpenGLPolyDataMapper::GetNeedToRebuildBufferObjects):
  // so all actors of a pass share one property, or a mesh shared by many objects would be
  // uploaded again for each of them, every frame.
  // The colour pass's lit actors and wires share a shader property too (`shader`).
  static vtkSmartPointer<vtkActor> actor(vtkPolyDataMapper* mapper, vtkProperty* property,
                                         vtkShaderProperty* shader = nullptr) {
    auto a = vtkSmartPointer<vtkActor>::New();
    a->SetMapper(mapper);
    a->SetProperty(property);
    if (shader != nullptr)
      a->SetShaderProperty(shader);
    a->ForceOpaqueOn();  // saves scanning the colours for alpha on every render
    return a;
  }

  // The entry of the thing at `key` of `tile`, marked as used; a new one (no actors yet, a slot
  // taken) if there was none or it was made from an earlier copy of the tile.
  DrawnEntry& entry(std::pair<scene::TileIndex, std::uint32_t> key,
                    const std::shared_ptr<const scene::Tile>& tile) {
    // Out of slots: what this render has not drawn (kept for the renders to come) gives its
    // own back, so only more than 65535 things in one picture are too many, whatever the
    // renders before it were (with several threads, their order varies).
    if (gl->free_slots.empty() && gl->next_slot >= kSlots && !gl->drawn.contains(key))
      forget(1);
    DrawnEntry& e = gl->drawn[key];
    if (e.tile && e.tile != tile)  // the tile was made again since
      drop(e);
    if (!e.tile) {
      e.tile = tile;
      e.slot = takeSlot();
    }
    e.used = gl->frame;
    return e;
  }

  DrawnEntry& objectEntry(std::pair<scene::TileIndex, std::uint32_t> key,
                          const std::shared_ptr<const scene::Tile>& tile,
                          const scene::Object& object, int level) {
    DrawnEntry& e = entry(key, tile);
    const MeshEntry& m = meshEntry(object.mesh, level);
    e.level = level;
    e.triangles = m.levels[level].triangles;
    if (!e.colour[level]) {
      e.colour[level] = actor(m.levels[level].mapper, gl->lit, gl->lit_shader);
      e.shares_colour_mapper = true;
      e.id[level] = actor(colourMapper(idPolyData(m.levels[level].poly, e.slot), "id"), gl->unlit);
      if (m.levels[level].glow_mapper)
        e.glow[level] = actor(m.levels[level].glow_mapper, gl->glow);
    }
    return e;
  }

  DrawnEntry& wireEntry(std::pair<scene::TileIndex, std::uint32_t> key,
                        const std::shared_ptr<const scene::Tile>& tile, const scene::Wire& wire) {
    DrawnEntry& e = entry(key, tile);
    if (!e.colour[0]) {
      const vtkSmartPointer<vtkPolyData> poly = wirePolyData(wire, e.slot);
      const vtkSmartPointer<vtkPolyDataMapper> mapper = colourMapper(poly, "albedo");
      mapper->AddObserver(vtkCommand::UpdateShaderEvent, gl->wire_uniforms);
      e.colour[0] = actor(mapper, gl->wire, gl->wire_shader);
      e.id[0] = actor(colourMapper(poly, "id"), gl->unlit);
    }
    return e;
  }

  // Frees an entry's OpenGL buffers (a shared mesh's go with the mesh's entry) and its slot.
  void drop(DrawnEntry& e) {
    for (int l = 0; l < kLevels; ++l) {
      if (e.colour[l] && !e.shares_colour_mapper)
        e.colour[l]->ReleaseGraphicsResources(gl->window);
      if (e.id[l])
        e.id[l]->ReleaseGraphicsResources(gl->window);
    }
    gl->free_slots.push_back(e.slot);
    e = DrawnEntry{};
  }

  // Drops the entries not drawn in the last `keep` renders (this one included), and with
  // kKeepRenders the meshes too (an entry's mesh was used when it was).
  void forget(std::uint64_t keep = kKeepRenders) {
    for (auto it = gl->drawn.begin(); it != gl->drawn.end();)
      if (it->second.used + keep <= gl->frame) {
        drop(it->second);
        it = gl->drawn.erase(it);
      } else {
        ++it;
      }
    if (keep < kKeepRenders)
      return;
    for (auto it = gl->meshes.begin(); it != gl->meshes.end();)
      if (it->second.used + kKeepRenders <= gl->frame) {
        for (MeshLevel& m : it->second.levels)
          for (vtkPolyDataMapper* mapper : {m.mapper.Get(), m.glow_mapper.Get()})
            if (mapper != nullptr)
              mapper->ReleaseGraphicsResources(gl->window);
        it = gl->meshes.erase(it);
      } else {
        ++it;
      }
  }

  // The colour pass's lights, placed relative to the camera (world axes, as the actors): the
  // day's sun and lamps, then, with `shade`, the shade's (its sun only if it shines). The sun
  // stays on at night, at intensity 0: with no light on at all, VTK would draw every surface
  // unlit, at its full colour. The renderer holds exactly these, in this order (which of them
  // is which, the lit shader's replacements are written for: setShadeShader()).
  void setLights(const Lighting& day, const Lighting* shade, const Eigen::Matrix3d& R_world_cam) {
    std::size_t n = 0;
    const auto next = [&]() -> vtkLight* {
      if (gl->lights.size() <= n) {
        auto light = vtkSmartPointer<vtkLight>::New();
        light->SetLightTypeToSceneLight();
        gl->lights.push_back(light);
      }
      return gl->lights[n++];
    };
    const auto sun = [&](const Lighting& l) {
      vtkLight* light = next();
      light->SetPositional(false);
      light->SetPosition(l.sun_direction.data());
      light->SetFocalPoint(0.0, 0.0, 0.0);
      light->SetIntensity(l.sun_intensity);
    };
    const auto spots = [&](const Lighting& l) {
      for (const Spot& s : l.spots) {
        vtkLight* light = next();
        const Eigen::Vector3d p = R_world_cam * s.position;
        const Eigen::Vector3d f = p + R_world_cam * s.direction;
        light->SetPositional(true);
        light->SetPosition(p.data());
        light->SetFocalPoint(f.data());
        light->SetConeAngle(s.half_angle_deg);
        light->SetExponent(2.0);  // brightest on the axis, fading towards the cone's edge
        light->SetAttenuationValues(1.0, 0.0, 1.0 / (s.half_distance_m * s.half_distance_m));
        light->SetIntensity(s.intensity);
      }
    };
    sun(day);
    spots(day);
    const int day_lights = static_cast<int>(n);
    if (shade != nullptr) {
      if (shade->sun_intensity > 0.0)
        sun(*shade);
      spots(*shade);
    }
    if (n > static_cast<std::size_t>(kMostLights))
      throw ConfigError("camera: more than 16 lights (a sun and lamps, by day and in the shade)");
    if (n != gl->lights_on) {  // a light added or taken away: the shaders are written again
      gl->renderer->RemoveAllLights();
      for (std::size_t i = 0; i < n; ++i)
        gl->renderer->AddLight(gl->lights[i]);
      gl->lights_on = n;
    }
    if (day_lights != gl->day_lights) {
      setShadeShader(gl->lit_shader, true, day_lights);
      gl->day_lights = day_lights;
    }
  }

  // The lightest level whose cells, scaled by the object's largest stretch, span at most
  // `pixels` at the nearest point of the object's box (0 inside it).
  static int levelOf(const scene::Object& object, const Eigen::Vector3d& eye, double focal_px,
                     double pixels) {
    if (!(pixels > 0.0))
      return 0;
    const Eigen::Vector3d nearest = eye.cwiseMax(object.bounds.min).cwiseMin(object.bounds.max);
    const double d = (nearest - eye).norm();
    const double stretch = object.linear.cast<double>().colwise().norm().maxCoeff();
    int level = 0;
    while (level + 1 < kLevels && focal_px * cellSize(level + 1) * stretch <= pixels * d)
      ++level;
    return level;
  }

  // Makes `actors` the renderer's props, in this order. The collection is set directly:
  // vtkViewport's Add/RemoveViewProp would free each removed actor's OpenGL buffers and shaders,
  // so every frame would upload all geometry and compile all shaders again (3/4 of a frame's
  // time); here an actor keeps them as long as its entry lives (drop()). The order is the
  // window's, so which of two surfaces at the same depth wins never depends on history.
  void show(const std::vector<vtkActor*>& actors) {
    vtkPropCollection* props = gl->renderer->GetViewProps();
    props->RemoveAllItems();
    for (vtkActor* a : actors)
      props->AddItem(a);
  }

  // Sets the colour pass's lights, the shader's inputs and the sky: by day where `shares` is
  // null, else each surface by its share of daylight (`shares`: the pixels' shares, rows top
  // to bottom), lit by `day` and `shade` in proportion. The sky is the day's.
  void light(const Intrinsics& k, const Lighting& day, const Lighting* shade,
             const std::vector<float>* shares, const Eigen::Matrix3d& R_world_cam) {
    const Lighting& dark = shares != nullptr ? *shade : day;
    setLights(day, shares != nullptr ? shade : nullptr, R_world_cam);
    gl->lit_inputs.light = {static_cast<float>(day.ambient), static_cast<float>(dark.ambient),
                            static_cast<float>(1.0 - day.ambient),
                            static_cast<float>(1.0 - dark.ambient)};
    // A wire is a line, which has no normal for VTK to light: it is shaded by one factor, the
    // sky's light and half the sun's (the mean over a thin cylinder's faces, roughly), so it
    // is dark at night instead of drawn at its full colour.
    const auto wire = [](const Lighting& l) {
      return static_cast<float>(l.ambient + 0.5 * (1.0 - l.ambient) * l.sun_intensity);
    };
    gl->wire_inputs.light = {wire(day), wire(dark), 0.0f, 0.0f};
    // The shares' texture is bound whether it is read or not: a sampler left on a unit that
    // VTK binds a texture of another type to (a mapper's cell colours) stops every draw.
    if (shares != nullptr) {
      // The texture's rows are OpenGL's, bottom-up.
      std::vector<float> rows(shares->size());
      for (int y = 0; y < k.height; ++y)
        std::copy_n(shares->data() + static_cast<std::size_t>(y) * k.width, k.width,
                    rows.data() + static_cast<std::size_t>(k.height - 1 - y) * k.width);
      gl->shares->Create2DFromRaw(k.width, k.height, 1, VTK_FLOAT, rows.data());
    } else if (gl->shares->GetWidth() != 1 || gl->shares->GetHeight() != 1) {
      float full = 1.0f;
      gl->shares->Create2DFromRaw(1, 1, 1, VTK_FLOAT, &full);
    }
    gl->shares->Activate();
    gl->lit_inputs.unit = gl->wire_inputs.unit = gl->shares->GetTextureUnit();
    gl->lit_inputs.shaded = gl->wire_inputs.shaded = shares != nullptr ? 1 : 0;
    vtkRenderer* ren = gl->renderer;
    ren->GradientBackgroundOn();
    ren->SetBackground(day.sky_horizon[0] / 255.0, day.sky_horizon[1] / 255.0,
                       day.sky_horizon[2] / 255.0);
    ren->SetBackground2(day.sky_zenith[0] / 255.0, day.sky_zenith[1] / 255.0,
                        day.sky_zenith[2] / 255.0);
  }

  // The window's colour, 3 bytes a pixel, rows top to bottom (OpenGL's are bottom-up).
  std::vector<std::uint8_t> readColour(const Intrinsics& k) {
    vtkNew<vtkUnsignedCharArray> rgb;
    gl->window->GetPixelData(0, 0, k.width - 1, k.height - 1, 0, rgb, 0);
    std::vector<std::uint8_t> out(3 * static_cast<std::size_t>(k.width) * k.height);
    for (int y = 0; y < k.height; ++y)
      std::copy_n(rgb->GetPointer(3 * static_cast<vtkIdType>(y) * k.width), 3 * k.width,
                  out.data() + 3 * static_cast<std::size_t>(k.height - 1 - y) * k.width);
    return out;
  }

  // Metres along the optical axis, rows top to bottom; 0 where nothing is drawn.
  std::vector<float> readDepth(const Intrinsics& k, const RendererOptions& o) {
    vtkNew<vtkFloatArray> z;
    gl->window->GetZbufferData(0, 0, k.width - 1, k.height - 1, z);
    std::vector<float> out(static_cast<std::size_t>(k.width) * k.height);
    for (int y = 0; y < k.height; ++y)
      for (int x = 0; x < k.width; ++x) {
        const float d = z->GetValue(static_cast<vtkIdType>(y) * k.width + x);
        out[static_cast<std::size_t>(k.height - 1 - y) * k.width + x] =
            d < 1.0f ? static_cast<float>(depthFromBuffer(d, o.near_m, o.far_m)) : 0.0f;
      }
    return out;
  }

  // The daylight share of the surface each pixel shows (its point: the pixel's ray at the
  // depth read back); 1 for the sky.
  static std::vector<float> daylightShares(const Intrinsics& k, const RendererOptions& o,
                                           const std::vector<float>& z,
                                           const Eigen::Isometry3d& T_world_cam) {
    std::vector<float> day(z.size(), 1.0f);
    std::vector<Eigen::Vector3d> points;
    std::vector<std::size_t> at;
    for (int y = 0; y < k.height; ++y)
      for (int x = 0; x < k.width; ++x) {
        const std::size_t i = static_cast<std::size_t>(y) * k.width + x;
        if (z[i] <= 0.0f)
          continue;
        const double d = z[i];
        points.push_back(T_world_cam *
                         Eigen::Vector3d((x - k.cx) / k.fx * d, (y - k.cy) / k.fy * d, d));
        at.push_back(i);
      }
    std::vector<float> shares(points.size());
    o.daylight(points, shares);
    for (std::size_t j = 0; j < at.size(); ++j)
      day[at[j]] = shares[j];
    return day;
  }

  CameraImages render(const RendererOptions& o, const scene::SceneWindow& window,
                      const Eigen::Isometry3d& T_world_cam, const Lighting& lighting,
                      const Lighting* shade) {
    if (!gl)
      start(o);
    ++gl->frame;
    const Intrinsics& k = o.intrinsics;
    CameraImages out;
    out.width = k.width;
    out.height = k.height;

    // What is in view, in the window's order, placed relative to the camera.
    const Eigen::Vector3d origin = T_world_cam.translation();
    const Frustum frustum(k, o.near_m, o.far_m, T_world_cam.inverse());
    std::vector<DrawnEntry*> list;
    // Whether a thing may be out of full daylight (worked out once: things do not move).
    const auto noteShade = [&](DrawnEntry& e, const scene::Box3d& box) {
      if (e.shade < 0)
        e.shade = !o.shade_meets || o.shade_meets(box) ? 1 : 0;
    };
    for (const auto& tile : window.tiles) {
      for (std::size_t i = 0; i < tile->objects.size(); ++i) {
        const scene::Object& object = tile->objects[i];
        if (o.cull && !frustum.meets(object.bounds))
          continue;
        DrawnEntry& e = objectEntry({tile->index, static_cast<std::uint32_t>(i)}, tile, object,
                                    levelOf(object, origin, std::max(k.fx, k.fy), o.lod_pixels));
        noteShade(e, object.bounds);
        place(e, object.linear.cast<double>(), object.position - origin);
        list.push_back(&e);
        noteInstance(out, e.slot, object.instance);
      }
      for (std::size_t i = 0; i < tile->wires.size(); ++i) {
        const scene::Wire& wire = tile->wires[i];
        const scene::Box3d bounds = wireBounds(*tile, wire);
        if (o.cull && !frustum.meets(bounds))
          continue;
        DrawnEntry& e = wireEntry(
            {tile->index, static_cast<std::uint32_t>(tile->objects.size() + i)}, tile, wire);
        place(e, Eigen::Matrix3d::Identity(), tile->origin - origin);
        noteShade(e, bounds);
        list.push_back(&e);
        noteInstance(out, e.slot, wire.instance);
      }
    }
    for (const DrawnEntry* e : list)
      out.triangles += e->triangles;
    out.objects = static_cast<std::int64_t>(list.size());

    // The camera at the origin looking along its z axis, y down.
    vtkCamera* cam = gl->renderer->GetActiveCamera();
    const Eigen::Matrix3d R = T_world_cam.linear();
    const Eigen::Vector3d forward = R.col(2), up = -R.col(1);
    cam->SetPosition(0.0, 0.0, 0.0);
    cam->SetFocalPoint(forward.x(), forward.y(), forward.z());
    cam->SetViewUp(up.x(), up.y(), up.z());

    const std::size_t pixels = static_cast<std::size_t>(k.width) * k.height;
    vtkRenderer* ren = gl->renderer;
    std::vector<vtkActor*> actors;
    // Only a frame in which something drawn may be out of full daylight pays for the shares:
    // the id pass is drawn first then, and its depth gives each pixel's surface.
    const bool may_shade =
        shade != nullptr && o.daylight && o.passes.rgb &&
        std::any_of(list.begin(), list.end(), [](const DrawnEntry* e) { return e->shade == 1; });
    std::vector<float> z;  // metres along the optical axis, 0 where nothing is drawn
    if ((o.passes.semantic || o.passes.instance || may_shade)) {
      actors.resize(list.size());
      std::transform(list.begin(), list.end(), actors.begin(),
                     [](const DrawnEntry* e) { return e->idActor(); });
      show(actors);
      ren->GradientBackgroundOff();
      ren->SetUseFXAA(false);  // ids are never blended
      ren->SetBackground(scene::cls::kSky / 255.0, 0.0, 0.0);
      gl->window->Render();
      // What the depth buffer holds at the far plane is nothing drawn, as the depth image
      // reads it: a fragment within a rounding of the far plane is drawn into the ids but
      // leaves the depth buffer at 1, and would be a class without a depth. The colour pass
      // draws the same triangles at the same places: its depth is this.
      z = readDepth(k, o);
      vtkNew<vtkUnsignedCharArray> ids;
      if (o.passes.semantic || o.passes.instance)
        gl->window->GetPixelData(0, 0, k.width - 1, k.height - 1, 0, ids, 0);
      if (o.passes.semantic)
        out.semantic.resize(pixels);
      if (o.passes.instance)
        out.object.resize(pixels);
      for (int y = 0; y < k.height && (o.passes.semantic || o.passes.instance); ++y)
        for (int x = 0; x < k.width; ++x) {
          const unsigned char* c = ids->GetPointer(3 * (static_cast<vtkIdType>(y) * k.width + x));
          const std::size_t i = static_cast<std::size_t>(k.height - 1 - y) * k.width + x;
          const bool drawn = z[i] > 0.0f;
          if (o.passes.semantic)
            out.semantic[i] = drawn ? c[0] : scene::cls::kSky;
          if (o.passes.instance)
            out.object[i] = drawn ? static_cast<std::uint16_t>(c[1] << 8 | c[2]) : 0;
        }
    }
    if (o.passes.rgb || (o.passes.depth && z.empty())) {
      // Each surface lit by its share of daylight where some pixel shows one out of full
      // daylight; by day everywhere else.
      std::vector<float> day;
      if (may_shade) {
        day = daylightShares(k, o, z, T_world_cam);
        if (std::all_of(day.begin(), day.end(), [](float d) { return d >= 1.0f; }))
          day.clear();
      }
      actors.clear();
      for (const DrawnEntry* e : list) {
        actors.push_back(e->colourActor());
        if (vtkActor* glow = e->glowActor())
          actors.push_back(glow);
      }
      show(actors);
      ren->SetUseFXAA(o.fxaa && o.passes.rgb);
      light(k, lighting, shade, day.empty() ? nullptr : &day, R);
      gl->window->Render();
      gl->shares->Deactivate();
      if (o.passes.rgb)
        out.rgb = readColour(k);
      if (z.empty() && o.passes.depth)
        z = readDepth(k, o);
    }
    if (o.passes.depth)
      out.depth = std::move(z);
    show({});
    forget();
    return out;
  }
};

Renderer::Renderer(RendererOptions options)
    : options_(std::move(options)), impl_(std::make_unique<Impl>()) {
  if (options_.intrinsics.width < 1 || options_.intrinsics.height < 1 || !(options_.near_m > 0.0) ||
      !(options_.far_m > options_.near_m))
    throw ConfigError("camera: the image must have pixels and 0 < near < far");
}

Renderer::~Renderer() = default;

CameraImages Renderer::render(const scene::SceneWindow& window,
                              const Eigen::Isometry3d& T_world_cam, const Lighting& lighting,
                              const Lighting* shade) const {
  return impl_->thread->run(
      [&] { return impl_->render(options_, window, T_world_cam, lighting, shade); });
}

}  // namespace trainsim::camera
