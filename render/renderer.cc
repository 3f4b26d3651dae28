#include "render/renderer.h"

#include <glad/gl.h>
#include <malloc.h>

#include <algorithm>
#include <cmath>
#include <mutex>
#include <stdexcept>

#include "core/numbers.h"

namespace colosim {

namespace {

// Display colour of red-out where the lens in the tissue sees no wall surface (the
// shader's kRedoutAlbedo at a few mm, tone mapped).
constexpr float kRedoutClear[3] = {0.62f, 0.13f, 0.09f};
// The onboard view switches from per-vertex to per-pixel (exact) barrel distortion when
// one of probeLumen's rays meets the wall this close to the lens [m] (the wall is then
// within 4-7 mm; per-vertex distortion smears from ~3 mm and leaves holes beside long
// facets); and draws the rectilinear image at this multiple of the viewport's size.
constexpr double kExactDistortionReach_m = 0.007;
constexpr double kExactOversample = 1.5;

// Wall and scope. MODE (a #define, one program per mode: a uniform branch costs llvmpipe
// both sides per pixel): 0 onboard wall (texture, tip light), 1 onboard solid (scope),
// 2 global wall (see-through), 3 global solid (scope, tip highlighted).
const char* kSceneVs = R"(#version 330 core
layout(location = 0) in vec3 a_pos;   // [m], world
layout(location = 1) in vec3 a_nrm;
layout(location = 2) in vec2 a_uv;
uniform mat4 u_view_proj;
// Onboard barrel distortion, per vertex: an equidistant lens puts the direction at angle
// theta from the axis at normalised radius theta / half_angle (1 at the image corners).
uniform bool u_fisheye;
uniform mat4 u_view;         // world to camera (GL axes: looking down -z)
uniform float u_half_angle;  // half the diagonal field of view [rad]
uniform float u_aspect;      // width / height
uniform vec2 u_near_far;     // [m]
out vec3 v_pos;
out vec3 v_nrm;
out vec2 v_uv;
void main() {
  v_pos = a_pos;
  v_nrm = a_nrm;
  v_uv = a_uv;
  if (u_fisheye) {
    vec3 pc = (u_view * vec4(a_pos, 1.0)).xyz;
    float d = length(pc);
    float rxy = length(pc.xy);
    float theta = atan(rxy, -pc.z);  // 0 on the axis .. pi behind
    float diag = sqrt(1.0 + u_aspect * u_aspect);
    vec2 dir = rxy > 1e-12 ? pc.xy / rxy : vec2(0.0);
    vec2 ndc = dir * (theta / u_half_angle) * diag / vec2(u_aspect, 1.0);
    // w = the distance: positive all around the lens (no wrap behind the camera),
    // close to the view depth for perspective-correct interpolation; depth is the
    // distance between the near and far planes.
    float z = (d - u_near_far.x) / (u_near_far.y - u_near_far.x) * 2.0 - 1.0;
    gl_Position = vec4(ndc * d, z * d, d);
    // w = d never clips what lies behind the lens, and facets around it would map to
    // wedges across the image: clip at the plane u_near_far.x in front of the lens (the
    // view reaches 70 deg off axis at the corners, so nothing visible is lost).
    gl_ClipDistance[0] = -pc.z - u_near_far.x;
  } else {
    gl_Position = u_view_proj * vec4(a_pos, 1.0);
    gl_ClipDistance[0] = 1.0;
  }
}
)";

const char* kSceneFs = R"(
in vec3 v_pos;
in vec3 v_nrm;
in vec2 v_uv;
uniform vec3 u_eye;          // camera (and, onboard, tip light) position [m]
uniform sampler2D u_tex;
uniform vec3 u_color;
uniform float u_light_ref;   // distance of unit irradiance [m]
uniform float u_far;         // onboard far plane [m]: the light fades to nothing before it
uniform float u_exposure;
uniform vec2 u_alpha;        // global wall opacity: facing, grazing
uniform vec3 u_tip_color;
uniform vec3 u_tip_pos;      // [m]
uniform float u_tip_len;     // [m]
out vec4 o_color;
// Red-out: the colour of mucosa lit through from behind at contact, in linear light.
const vec3 kRedoutAlbedo = vec3(0.55, 0.035, 0.02);
void main() {
  // inversesqrt rather than length, normalize and divisions: llvmpipe runs this per pixel.
  vec3 V = u_eye - v_pos;
  float d2 = dot(V, V);
  float inv_d = inversesqrt(max(d2, 1e-12));
  V *= inv_d;
  vec3 N = v_nrm * inversesqrt(dot(v_nrm, v_nrm));
  float ndv = abs(dot(N, V));  // two-sided: the camera may see either face
#if MODE <= 1
    // Point light at the tip: irradiance falls off as 1 / d^2 (near wall bright, far
    // lumen dark). Light and eye coincide, so the Blinn half vector is V: sharp wet
    // highlights where the mucosa faces the tip, plus a broader sheen.
    // Shading is done in linear light (the texture holds display values; gamma 2 is
    // close enough to 2.2 and costs a multiply, which matters on llvmpipe), tone mapped
    // and gamma encoded at the end, as a camera's processor would.
#if MODE == 0
    vec3 t = texture(u_tex, v_uv).rgb;
#else
    vec3 t = u_color;
#endif
    vec3 albedo = t * t;
    float E = u_light_ref * u_light_ref * inv_d * inv_d;
    float d = d2 * inv_d;
    // Beyond ~0.7 far the 1 / d^2 light is already below 1 % of its reference; fading it
    // to zero at the far plane hides the cut, so the colon beyond need not be drawn.
    E *= 1.0 - smoothstep(0.7 * u_far, u_far, d);
    // Specular lobes ndv^128 (sharp wet glints) and ndv^16 (sheen) by repeated squaring.
    float n2 = ndv * ndv, n4 = n2 * n2, n8 = n4 * n4, n16 = n8 * n8, n32 = n16 * n16;
    float n128 = n32 * n32 * n32 * n32;
#if MODE == 0
    float spec = 0.8 * n128 + 0.05 * n16;
#else
    float spec = 0.4 * n32;
#endif
    // A little wrap-around light (0.15) keeps fold silhouettes from going pitch black.
    vec3 c = u_exposure * (albedo * (0.15 + 0.85 * ndv) + vec3(spec)) * E;
#if MODE == 0
    // The wall seen from its outside (front faces look into the lumen): the lens is in
    // the tissue, pressed into the soft wall or a fold, and sees the tip light through
    // the mucosa: red-out, a featureless red that the light still makes brighter nearby.
    if (!gl_FrontFacing) c = u_exposure * kRedoutAlbedo * (0.15 + 0.85 * ndv) * E;
#endif
    c = c / (1.0 + c);  // tone map: bright but never clipped flat
    c = sqrt(c);
    o_color = vec4(c, 1.0);
#elif MODE == 2
    // X-ray look: faint where the wall faces the viewer, denser along the outline.
    float g = 1.0 - ndv;
    float a = mix(u_alpha.x, u_alpha.y, g * g * g);
    o_color = vec4(u_color * (0.5 + 0.5 * ndv), a);
#else
    vec3 col = distance(v_pos, u_tip_pos) < u_tip_len ? u_tip_color : u_color;
    o_color = vec4(col * (0.35 + 0.65 * ndv) + vec3(0.3 * pow(ndv, 40.0)), 1.0);
#endif
}
)";

// Exact barrel distortion for a lens next to the wall: the view drawn rectilinear (same
// diagonal field of view) into a texture, resampled per pixel. A direction at angle
// theta from the axis lies at radius theta / half_angle on the equidistant image and
// tan(theta) / tan(half_angle) on the rectilinear one (both in half diagonals).
const char* kWarpVs = R"(#version 330 core
out vec2 v_ndc;
void main() {  // one triangle covering the viewport
  vec2 p = vec2(gl_VertexID == 1 ? 3.0 : -1.0, gl_VertexID == 2 ? 3.0 : -1.0);
  v_ndc = p;
  gl_Position = vec4(p, 0.0, 1.0);
}
)";

const char* kWarpFs = R"(#version 330 core
in vec2 v_ndc;
uniform sampler2D u_image;   // the rectilinear view
uniform float u_aspect;      // width / height
uniform float u_half_angle;  // half the diagonal field of view [rad]
out vec4 o_color;
void main() {
  float diag = sqrt(1.0 + u_aspect * u_aspect);
  vec2 q = v_ndc * vec2(u_aspect, 1.0) / diag;  // half diagonals: 1 at the corners
  float rho = length(q);
  float theta = rho * u_half_angle;
  float k = rho > 1e-6 ? tan(theta) / (rho * tan(u_half_angle)) : u_half_angle / tan(u_half_angle);
  vec2 ndc = q * k * diag / vec2(u_aspect, 1.0);
  o_color = texture(u_image, ndc * 0.5 + 0.5);
}
)";

GLuint compile(GLenum type, const char* src) {
  const GLuint s = glCreateShader(type);
  glShaderSource(s, 1, &src, nullptr);
  glCompileShader(s);
  GLint ok = 0;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[2048] = {};
    glGetShaderInfoLog(s, sizeof log, nullptr, log);
    glDeleteShader(s);
    throw std::runtime_error(std::string("render: shader compile failed: ") + log);
  }
  return s;
}

GLuint link(const char* vs, const char* fs) {
  const GLuint v = compile(GL_VERTEX_SHADER, vs), f = compile(GL_FRAGMENT_SHADER, fs);
  const GLuint p = glCreateProgram();
  glAttachShader(p, v);
  glAttachShader(p, f);
  glLinkProgram(p);
  glDeleteShader(v);
  glDeleteShader(f);
  GLint ok = 0;
  glGetProgramiv(p, GL_LINK_STATUS, &ok);
  if (!ok) {
    char log[2048] = {};
    glGetProgramInfoLog(p, sizeof log, nullptr, log);
    glDeleteProgram(p);
    throw std::runtime_error(std::string("render: shader link failed: ") + log);
  }
  return p;
}

struct MeshBuffers {
  GLuint vao = 0, vbo = 0, ebo = 0;
  GLsizei index_count = 0;
  std::vector<uint32_t> uploaded_indices;  // what the element buffer holds (re-sent only on change)

  void create() {
    glGenVertexArrays(1, &vao);
    glGenBuffers(1, &vbo);
    glGenBuffers(1, &ebo);
    glBindVertexArray(vao);
    glBindBuffer(GL_ARRAY_BUFFER, vbo);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, ebo);
    const GLsizei stride = TubeMesh::kFloatsPerVertex * sizeof(float);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<void*>(0));
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<void*>(3 * sizeof(float)));
    glEnableVertexAttribArray(2);
    glVertexAttribPointer(2, 2, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<void*>(6 * sizeof(float)));
    glBindVertexArray(0);
  }
  void upload(const TubeMesh& m) {
    uploadVertices(m);
    uploadIndices(m.indices);
  }
  void uploadVertices(const TubeMesh& m) {
    glBindBuffer(GL_ARRAY_BUFFER, vbo);
    glBufferData(GL_ARRAY_BUFFER, m.vertices.size() * sizeof(float), m.vertices.data(), GL_STREAM_DRAW);
  }
  void uploadIndices(const std::vector<uint32_t>& indices) {
    if (indices != uploaded_indices) {  // the topology rarely changes between frames (memcmp)
      glBindVertexArray(vao);           // the element buffer binding is VAO state
      glBufferData(GL_ELEMENT_ARRAY_BUFFER, indices.size() * sizeof(uint32_t), indices.data(), GL_STREAM_DRAW);
      glBindVertexArray(0);
      uploaded_indices = indices;
    }
    index_count = static_cast<GLsizei>(indices.size());
  }
  void draw() const {
    glBindVertexArray(vao);
    glDrawElements(GL_TRIANGLES, index_count, GL_UNSIGNED_INT, nullptr);
    glBindVertexArray(0);
  }
  void destroy() {
    glDeleteBuffers(1, &vbo);
    glDeleteBuffers(1, &ebo);
    glDeleteVertexArrays(1, &vao);
  }
};

void setMat4(GLuint prog, const char* name, const Mat4f& m) {
  glUniformMatrix4fv(glGetUniformLocation(prog, name), 1, GL_FALSE, m.data());  // column-major
}

void setVec3(GLuint prog, const char* name, const Vec3& v) {
  glUniform3f(glGetUniformLocation(prog, name), static_cast<float>(v.x()), static_cast<float>(v.y()),
              static_cast<float>(v.z()));
}

void setVec3(GLuint prog, const char* name, const std::array<float, 3>& v) {
  glUniform3f(glGetUniformLocation(prog, name), v[0], v[1], v[2]);
}

void useViewport(const Viewport& vp) {
  glViewport(vp.x, vp.y, vp.width, vp.height);
  glScissor(vp.x, vp.y, vp.width, vp.height);
  glEnable(GL_SCISSOR_TEST);  // clear only this view (split screens)
}

}  // namespace

struct Renderer::Gl {
  std::array<GLuint, 4> scene{};  // by MODE of kSceneFs
  GLuint warp = 0, warp_vao = 0;
  GLuint texture = 0;
  // The rectilinear target of the exact distortion (created on first use, resized as needed).
  GLuint exact_fbo = 0, exact_colour = 0, exact_depth = 0;
  int exact_w = 0, exact_h = 0;
  MeshBuffers colon, colon_global, scope;  // two colons: each view keeps its topology uploaded
  // The reduced-size target of the render scale (created on first use, resized as needed),
  // and the framebuffers bound before drawing into it.
  GLuint scaled_fbo = 0, scaled_colour = 0, scaled_depth = 0;
  int scaled_w = 0, scaled_h = 0;
  GLint prev_draw_fbo = 0, prev_read_fbo = 0;
  bool scaled_active = false;  // between beginScaled and endScaled at a scale below 1
};

Renderer::Renderer(const TubeOptions& tube, const MucosaOptions& mucosa)
    : tube_(tube), gl_(std::make_unique<Gl>()) {
  if (!glCreateShader)
    throw std::runtime_error("render: no GL loaded (make an OffscreenContext or Window first)");
  for (int mode = 0; mode < 4; ++mode) {
    const std::string fs = "#version 330 core\n#define MODE " + std::to_string(mode) + "\n" + kSceneFs;
    gl_->scene[mode] = link(kSceneVs, fs.c_str());
  }
  gl_->warp = link(kWarpVs, kWarpFs);
  glGenVertexArrays(1, &gl_->warp_vao);
  gl_->colon.create();
  gl_->colon_global.create();
  gl_->scope.create();

  const Image tex = makeMucosaTexture(mucosa);
  glGenTextures(1, &gl_->texture);
  glBindTexture(GL_TEXTURE_2D, gl_->texture);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, tex.width, tex.height, 0, GL_RGBA, GL_UNSIGNED_BYTE,
               tex.rgba.data());
  glGenerateMipmap(GL_TEXTURE_2D);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_REPEAT);
}

Renderer::~Renderer() {
  if (!glDeleteProgram) return;
  for (GLuint p : gl_->scene) glDeleteProgram(p);
  glDeleteProgram(gl_->warp);
  glDeleteVertexArrays(1, &gl_->warp_vao);
  if (gl_->exact_fbo) {
    glDeleteFramebuffers(1, &gl_->exact_fbo);
    glDeleteTextures(1, &gl_->exact_colour);
    glDeleteRenderbuffers(1, &gl_->exact_depth);
  }
  gl_->colon.destroy();
  gl_->colon_global.destroy();
  gl_->scope.destroy();
  glDeleteTextures(1, &gl_->texture);
  if (gl_->scaled_fbo) {
    glDeleteFramebuffers(1, &gl_->scaled_fbo);
    glDeleteRenderbuffers(1, &gl_->scaled_colour);
    glDeleteRenderbuffers(1, &gl_->scaled_depth);
  }
}

Viewport Renderer::beginScaled(const Viewport& vp, double scale) {
  if (!(scale >= 0.25 && scale <= 1.0)) throw std::invalid_argument("render: render_scale must be in [0.25, 1]");
  gl_->scaled_active = false;
  if (scale == 1.0) return vp;
  const int w = std::max(1, static_cast<int>(std::lround(vp.width * scale)));
  const int h = std::max(1, static_cast<int>(std::lround(vp.height * scale)));
  Gl& g = *gl_;
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &g.prev_draw_fbo);
  glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &g.prev_read_fbo);
  if (!g.scaled_fbo) {
    glGenFramebuffers(1, &g.scaled_fbo);
    glGenRenderbuffers(1, &g.scaled_colour);
    glGenRenderbuffers(1, &g.scaled_depth);
  }
  glBindFramebuffer(GL_FRAMEBUFFER, g.scaled_fbo);
  if (w != g.scaled_w || h != g.scaled_h) {
    glBindRenderbuffer(GL_RENDERBUFFER, g.scaled_colour);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, w, h);
    glBindRenderbuffer(GL_RENDERBUFFER, g.scaled_depth);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, w, h);
    glBindRenderbuffer(GL_RENDERBUFFER, 0);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, g.scaled_colour);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, g.scaled_depth);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
      glBindFramebuffer(GL_DRAW_FRAMEBUFFER, g.prev_draw_fbo);
      glBindFramebuffer(GL_READ_FRAMEBUFFER, g.prev_read_fbo);
      g.scaled_w = g.scaled_h = 0;
      throw std::runtime_error("render: the render-scale framebuffer is incomplete");
    }
    g.scaled_w = w, g.scaled_h = h;
  }
  g.scaled_active = true;
  return Viewport{0, 0, w, h};
}

void Renderer::endScaled(const Viewport& vp, const Viewport& drawn) {
  Gl& g = *gl_;
  if (!g.scaled_active) return;
  g.scaled_active = false;
  glBindFramebuffer(GL_READ_FRAMEBUFFER, g.scaled_fbo);
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, g.prev_draw_fbo);
  useViewport(vp);  // the blit honours the scissor: this view only
  glBlitFramebuffer(0, 0, drawn.width, drawn.height, vp.x, vp.y, vp.x + vp.width, vp.y + vp.height,
                    GL_COLOR_BUFFER_BIT, GL_LINEAR);
  glDisable(GL_SCISSOR_TEST);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, g.prev_read_fbo);
}

void Renderer::uploadMeshes(const ColonModel& model, const Points& q, const ScopeShape& scope,
                            const TubeOptions& options, bool global) {
  sampleColonRings(model, q, options, rings_);
  TubeMesh& mesh = global ? colon_global_mesh_ : colon_mesh_;
  buildColonMesh(rings_, options, mesh);
  if (global)
    gl_->colon_global.upload(mesh);
  else
    gl_->colon.uploadVertices(mesh);  // drawOnboard sends the triangles it draws
  if (scope.centreline_m.size() >= 2) {
    buildScopeMesh(scope, options, scope_mesh_);
    gl_->scope.upload(scope_mesh_);
  } else {
    scope_mesh_ = TubeMesh{};
    gl_->scope.index_count = 0;  // no scope yet (e.g. before insertion)
  }
}

void Renderer::drawOnboard(const ColonModel& model, const Points& q, const ScopeShape& scope,
                           const CameraPose& camera, const Viewport& vp, const OnboardOptics& optics) {
  if (vp.width <= 0 || vp.height <= 0) throw std::invalid_argument("render: empty viewport");
  checkCameraPose(camera);
  uploadMeshes(model, q, scope, tube_, /*global=*/false);
  const Viewport target = beginScaled(vp, optics.render_scale);
  const LumenProbe probe = probeLumen(colon_mesh_, rings_, camera.p_WC_m);
  // Per-vertex distortion draws a facet as the straight-edged triangle between its
  // projected vertices; next to the lens a facet spans a wide angle and that triangle
  // misses much of it, leaving holes. There draw rectilinear (exact for flat facets)
  // and resample per pixel.
  const bool exact = optics.barrel_distortion && probe.nearest_hit_m < kExactDistortionReach_m;
  GLint outer_fbo = 0;
  Viewport drawn = target;
  if (exact) {
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &outer_fbo);
    drawn = beginExact(target);
  }
  useViewport(drawn);
  // Beyond the far plane the lumen is dark; a lens in the tissue (pressed into the soft
  // wall) sees red wherever no wall surface lies in its view.
  if (probe.inside)
    glClearColor(0, 0, 0, 1);
  else
    glClearColor(kRedoutClear[0], kRedoutClear[1], kRedoutClear[2], 1);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glEnable(GL_DEPTH_TEST);
  glDepthMask(GL_TRUE);
  glDisable(GL_BLEND);
  glDisable(GL_CULL_FACE);

  const double aspect = static_cast<double>(vp.width) / vp.height;
  const double fov_y = verticalFovFromDiagonal(optics.fov_diagonal_deg * kPi / 180, aspect);
  const Mat4f vp_mat = perspectiveMatrix(fov_y, aspect, optics.near_m, optics.far_m) * viewMatrix(camera);
  // One program per MODE; uniforms a mode does not use are optimised out (location -1),
  // and glUniform ignores location -1.
  auto use = [&](int mode) {
    const GLuint p = gl_->scene[mode];
    glUseProgram(p);
    setMat4(p, "u_view_proj", vp_mat);
    setVec3(p, "u_eye", camera.p_WC_m);
    glUniform1f(glGetUniformLocation(p, "u_light_ref"), static_cast<float>(optics.light_ref_m));
    glUniform1f(glGetUniformLocation(p, "u_exposure"), static_cast<float>(optics.exposure));
    glUniform1f(glGetUniformLocation(p, "u_far"), static_cast<float>(optics.far_m));
    glUniform1i(glGetUniformLocation(p, "u_tex"), 0);
    glUniform1i(glGetUniformLocation(p, "u_fisheye"), optics.barrel_distortion && !exact ? 1 : 0);
    setMat4(p, "u_view", viewMatrix(camera));
    glUniform1f(glGetUniformLocation(p, "u_half_angle"),
                static_cast<float>(0.5 * optics.fov_diagonal_deg * kPi / 180));
    glUniform1f(glGetUniformLocation(p, "u_aspect"), static_cast<float>(aspect));
    glUniform2f(glGetUniformLocation(p, "u_near_far"), static_cast<float>(optics.near_m),
                static_cast<float>(optics.far_m));
    return p;
  };
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, gl_->texture);
  glEnable(GL_CLIP_DISTANCE0);
  use(0);
  // The colon: only what the view can see, far strips coarser (cheaper for llvmpipe,
  // which pays per vertex and per triangle), or all of it at full detail.
  if (optics.reduce_detail) {
    visibleDetailIndices(rings_, colon_mesh_.ring_vertices, camera.p_WC_m, camera.R_WC.col(2), optics.far_m,
                         0.5 * optics.fov_diagonal_deg * kPi / 180, DetailOptions{}, detail_indices_);
    gl_->colon.uploadIndices(detail_indices_);
  } else {
    gl_->colon.uploadIndices(colon_mesh_.indices);
  }
  gl_->colon.draw();
  if (gl_->scope.index_count > 0) {
    const GLuint p = use(1);
    setVec3(p, "u_color", std::array<float, 3>{0.12f, 0.12f, 0.13f});  // black insertion tube
    gl_->scope.draw();
  }
  glDisable(GL_CLIP_DISTANCE0);
  if (exact) {
    glBindFramebuffer(GL_FRAMEBUFFER, static_cast<GLuint>(outer_fbo));
    useViewport(target);
    glDisable(GL_DEPTH_TEST);
    glUseProgram(gl_->warp);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, gl_->exact_colour);
    glUniform1i(glGetUniformLocation(gl_->warp, "u_image"), 0);
    glUniform1f(glGetUniformLocation(gl_->warp, "u_aspect"), static_cast<float>(aspect));
    glUniform1f(glGetUniformLocation(gl_->warp, "u_half_angle"),
                static_cast<float>(0.5 * optics.fov_diagonal_deg * kPi / 180));
    glBindVertexArray(gl_->warp_vao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindVertexArray(0);
  }
  glDisable(GL_SCISSOR_TEST);
  glUseProgram(0);
  endScaled(vp, target);
}

Viewport Renderer::beginExact(const Viewport& target) {
  Gl& g = *gl_;
  // The rectilinear image is sparser than the equidistant one at the centre (by
  // (half_angle / tan(half_angle)) = 2.2 at 140 deg): draw it larger.
  const int w = std::max(1, static_cast<int>(std::lround(target.width * kExactOversample)));
  const int h = std::max(1, static_cast<int>(std::lround(target.height * kExactOversample)));
  if (!g.exact_fbo) {
    glGenFramebuffers(1, &g.exact_fbo);
    glGenTextures(1, &g.exact_colour);
    glGenRenderbuffers(1, &g.exact_depth);
  }
  glBindFramebuffer(GL_FRAMEBUFFER, g.exact_fbo);
  if (w != g.exact_w || h != g.exact_h) {
    glBindTexture(GL_TEXTURE_2D, g.exact_colour);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, w, h, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glBindRenderbuffer(GL_RENDERBUFFER, g.exact_depth);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, w, h);
    glBindRenderbuffer(GL_RENDERBUFFER, 0);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, g.exact_colour, 0);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, g.exact_depth);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
      g.exact_w = g.exact_h = 0;
      throw std::runtime_error("render: the exact-distortion framebuffer is incomplete");
    }
    g.exact_w = w, g.exact_h = h;
  }
  return Viewport{0, 0, w, h};
}

void Renderer::drawGlobal(const ColonModel& model, const Points& q, const ScopeShape& scope,
                          const OrbitCamera& camera, const Viewport& vp, const GlobalStyle& style) {
  if (vp.width <= 0 || vp.height <= 0) throw std::invalid_argument("render: empty viewport");
  TubeOptions coarse = tube_;
  coarse.sides = style.colon_sides;
  coarse.samples_per_segment = style.colon_samples_per_segment;
  coarse.haustra = false;
  uploadMeshes(model, q, scope, coarse, /*global=*/true);
  const Viewport target = beginScaled(vp, style.render_scale);
  useViewport(target);
  glClearColor(style.background[0], style.background[1], style.background[2], 1);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glEnable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);

  const CameraPose pose = camera.pose();
  const double aspect = static_cast<double>(vp.width) / vp.height;
  const Mat4f vp_mat = perspectiveMatrix(camera.fov_y_deg * kPi / 180, aspect, 0.05 * camera.distance_m,
                                         4 * camera.distance_m + 1.0) *
                       viewMatrix(pose);
  auto use = [&](int mode) {
    const GLuint p = gl_->scene[mode];
    glUseProgram(p);
    setMat4(p, "u_view_proj", vp_mat);
    setVec3(p, "u_eye", pose.p_WC_m);
    return p;
  };
  // The colon first, blended without writing depth, so every wall layer shows; then the
  // scope, opaque, over it: no wall layer in front of the scope can wash it out (the
  // scope's shape is what a scope-position display is for), and the scope still hides
  // itself where it crosses over (its own depth).
  glEnable(GL_BLEND);
  glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
  glDepthMask(GL_FALSE);
  {
    const GLuint p = use(2);
    setVec3(p, "u_color", style.colon_rgb);
    glUniform2f(glGetUniformLocation(p, "u_alpha"), style.colon_alpha_face, style.colon_alpha_silhouette);
    gl_->colon_global.draw();
  }
  glDepthMask(GL_TRUE);
  glDisable(GL_BLEND);
  if (gl_->scope.index_count > 0) {
    glClear(GL_DEPTH_BUFFER_BIT);  // the colon wrote none: only the scope's own depth counts
    const GLuint p = use(3);
    setVec3(p, "u_color", style.scope_rgb);
    setVec3(p, "u_tip_color", style.tip_rgb);
    setVec3(p, "u_tip_pos", scope.centreline_m.back());
    glUniform1f(glGetUniformLocation(p, "u_tip_len"), static_cast<float>(style.tip_length_m));
    gl_->scope.draw();
  }
  glDepthMask(GL_TRUE);
  glDisable(GL_BLEND);
  glDisable(GL_SCISSOR_TEST);
  glUseProgram(0);
  endScaled(vp, target);
}

Image readFramebuffer(const Viewport& vp) {
  Image img(vp.width, vp.height);
  glFinish();
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(vp.x, vp.y, vp.width, vp.height, GL_RGBA, GL_UNSIGNED_BYTE, img.rgba.data());
  // GL rows come bottom-up: flip in place (no second frame-sized buffer per frame).
  const size_t stride = static_cast<size_t>(vp.width) * 4;
  for (int y = 0; y < vp.height / 2; ++y)
    std::swap_ranges(img.at(0, y), img.at(0, y) + stride, img.at(0, vp.height - 1 - y));
  return img;
}

void keepDriverMemoryBetweenFrames() {
  static std::once_flag once;
  std::call_once(once, [] { mallopt(M_TRIM_THRESHOLD, 128 << 20); });
}

std::vector<unsigned> drainGlErrors() {
  std::vector<unsigned> errors;
  for (GLenum e = glGetError(); e != GL_NO_ERROR && errors.size() < 64; e = glGetError()) errors.push_back(e);
  return errors;
}

}  // namespace colosim
