#pragma once
// Private to the camera module: the colour pass's shader replacements that light each surface
// by its share of daylight (renderer.cpp).
#include <array>

class vtkObject;
class vtkOpenGLShaderProperty;

namespace trainsim::camera {

// Each surface lit by the daylight that reaches it, in one colour pass. Light is linear in the
// share s of daylight a surface gets, so its colour s × (its colour by day) + (1 − s) × (its
// colour in the shade) is that of one lighting: the ambient s·a_day + (1 − s)·a_shade, the
// day's lights weighted by s·(1 − a_day) and the shade's by (1 − s)·(1 − a_shade) (a lighting's
// diffuse share is 1 − its ambient). VTK writes the lighting's shader; these replacements
// weight its terms per fragment, by the share of the pixel's surface read from a texture
// (worked out from the id pass's depth). GLSL's preprocessor, as C's, leaves a macro's name
// unexpanded within its own expansion, so `#define lightColor0 (lightColor0 * w)` weights the
// uniform wherever the lighting code reads it; the defines follow the uniforms' declarations.
//
// The most lights a colour pass has (the replacements weight this many).
inline constexpr int kMostLights = 16;

// What the replacements read, per render: set by the renderer, handed to the shaders by
// setShadeUniforms().
struct ShadeInputs {
  int unit = 0;                  // the shares' texture unit
  int shaded = 0;                // 0: daylight everywhere (the texture is not read)
  std::array<float, 4> light{};  // ambient by day, in the shade; diffuse by day, in the shade
};

// Gives `p` the replacements: for lit surfaces (`lit`), lights 0 … day_lights − 1 the day's
// and the rest the shade's; else for a surface drawn without lights (a wire), its colour scaled
// by the ambient alone.
void setShadeShader(vtkOpenGLShaderProperty* p, bool lit, int day_lights);

// A vtkCommand callback for a colour mapper's UpdateShaderEvent: sets its shader's uniforms
// from the ShadeInputs `client`.
void setShadeUniforms(vtkObject*, unsigned long, void* client, void* program);

}  // namespace trainsim::camera
