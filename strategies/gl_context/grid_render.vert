#version 330 core
// Drawing an evaluated grid as triangles (002 §4.1/§4.2, and 000's rendering pass). VERTEX_FETCH 1:
// the static index buffer's index k = b * nu + a is turned into the evaluated point by vertex
// texture fetch from the strategy's output texture (002 §4.2, no read-back): texel
// origin + (a, b), or origin + (b, a) when the strategy lays u along y. VERTEX_FETCH 0: the
// "traditional" path of 002 §4.1, the same points read back and re-uploaded as a vertex buffer.
// Trimmed surfaces (000 §4) also carry each vertex's (u, v) in trim-texture coordinates, fetched
// from the sample table row 0 (u) and row 1 (v), for the fragment shader's trim lookup.
uniform mat4 mvp;
// Vertex k is b * nu + a; with v_major set it is a * nu + b and `nu` holds nv (000 §3.2's device
// copies, whose rows are the output texture's: only the trim lookup needs (a, b) then).
uniform int nu;
uniform int v_major;
#if VERTEX_FETCH
uniform sampler2D points;
uniform ivec2 origin;
uniform int u_along_x;
#else
layout(location = 0) in vec3 position;
#endif
uniform int trimmed;
uniform sampler2D parameters;
uniform ivec2 first_sample;  // (first u, first v) of this grid in the sample table
out vec2 trim_uv;
out vec3 clip_position;  // for the fragment stage's facet normal

void main() {
  int k = gl_VertexID;
  int a = v_major != 0 ? k / nu : k % nu;
  int b = v_major != 0 ? k % nu : k / nu;
#if VERTEX_FETCH
  ivec2 texel = u_along_x != 0 ? ivec2(a, b) : ivec2(b, a);
  vec3 position = texelFetch(points, origin + texel, 0).xyz;
#endif
  trim_uv = vec2(0.0);
  if (trimmed != 0)
    trim_uv = vec2(texelFetch(parameters, ivec2(first_sample.x + a, 0), 0).g,
                   texelFetch(parameters, ivec2(first_sample.y + b, 1), 0).g);
  gl_Position = mvp * vec4(position, 1.0);
  clip_position = gl_Position.xyz / gl_Position.w;
}
