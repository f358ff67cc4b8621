#version 460
// Heights of a height grid at a list of points: bilinear between the grid's vertices, the point
// clamped into the grid's box, as sampleHeight (engine/loss/metrics.cpp) is in double, the
// reference. The known-water oracle's surface where the dataset's true water has no closed form
// AnalyticWaves holds (a height map in water.json, engine/height/grid_height.h).
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) readonly buffer Points { vec2 points[]; };
layout(std430, set = 0, binding = 1) writeonly buffer Heights { float heights[]; };
layout(std430, set = 0, binding = 2) readonly buffer Grid { float grid[]; };  // row j at y = yMin + j (yMax - yMin) / (ny - 1)
layout(push_constant) uniform Push { vec4 box; int nx; int ny; uint count; } pc;  // box: xMin, yMin, xMax, yMax
void main() {
  uint k = gl_GlobalInvocationID.x;
  if (k >= pc.count) return;
  vec2 p = points[k];
  // A point that is not finite (a lane past a queued count reads what the buffer holds) has no
  // height: clamp() of NaN is undefined, and its cell index would read outside the grid.
  if (any(isnan(p)) || any(isinf(p))) {
    heights[k] = uintBitsToFloat(0x7FC00000u);
    return;
  }
  float fx = clamp((p.x - pc.box.x) / (pc.box.z - pc.box.x), 0.0, 1.0) * float(pc.nx - 1);
  float fy = clamp((p.y - pc.box.y) / (pc.box.w - pc.box.y), 0.0, 1.0) * float(pc.ny - 1);
  int i = min(int(fx), pc.nx - 2), j = min(int(fy), pc.ny - 2);
  float u = fx - float(i), v = fy - float(j);
  int at = j * pc.nx + i;
  heights[k] = mix(mix(grid[at], grid[at + 1], u), mix(grid[at + pc.nx], grid[at + pc.nx + 1], u), v);
}
