#version 330 core
// Voxel index space has x right, y down, z away from the viewer (image-stack order), so the
// painter's slices and the 3D view agree; world space is right-handed with y up.

uniform mat4 u_inv_view_proj;
uniform vec3 u_eye;
uniform vec3 u_extent;      // half extents of the box in world units
uniform vec3 u_voxels;      // volume size (w, h, d)
uniform sampler3D u_volume;
uniform float u_steps;      // cl_steps: samples per unit of texture-space length (S = cl_steps * |AB|)
uniform vec3 u_background;
uniform int u_plane_axis[2];    // -1: none; 0, 1, 2: a slice across x, y, z (index space)
uniform float u_plane_pos[2];   // its centre, in texture coordinates
uniform vec4 u_plane_color[2];

in vec2 v_ndc;
out vec4 frag_color;

vec3 to_texture(vec3 p) {
    return (p * vec3(1.0, -1.0, -1.0) / u_extent + 1.0) * 0.5;
}

void blend(inout vec4 acc, vec3 rgb, float alpha) {
    acc.rgb += (1.0 - acc.a) * alpha * rgb;
    acc.a += (1.0 - acc.a) * alpha;
}

void main() {
    vec4 far = u_inv_view_proj * vec4(v_ndc, 1.0, 1.0);
    vec3 dir = normalize(far.xyz / far.w - u_eye);
    vec3 inv = 1.0 / dir;
    vec3 t0 = (-u_extent - u_eye) * inv;
    vec3 t1 = (u_extent - u_eye) * inv;
    vec3 tmin = min(t0, t1);
    vec3 tmax = max(t0, t1);
    float t_near = max(max(tmin.x, tmin.y), max(tmin.z, 0.0));  // 0: the camera may be inside
    float t_far = min(min(tmax.x, tmax.y), tmax.z);
    if (t_near >= t_far) {
        frag_color = vec4(u_background, 1.0);
        return;
    }
    vec3 a = to_texture(u_eye + dir * t_near);
    vec3 b = to_texture(u_eye + dir * t_far);
    int n = max(1, int(ceil(u_steps * length(b - a))));
    vec3 step = (b - a) / float(n);
    float voxels_per_step = length(step * u_voxels);  // voxel alpha is per voxel: correct for the step
    vec4 acc = vec4(0.0);
    vec3 prev = a;
    for (int i = 0; i < n && acc.a < 0.995; ++i) {
        vec3 p = a + step * (float(i) + 0.5);
        for (int k = 0; k < 2; ++k) {  // slice planes crossed since the last sample
            int axis = u_plane_axis[k];
            if (axis >= 0 && (prev[axis] - u_plane_pos[k]) * (p[axis] - u_plane_pos[k]) <= 0.0 && i > 0)
                blend(acc, u_plane_color[k].rgb, u_plane_color[k].a);
        }
        vec4 s = texture(u_volume, p);
        blend(acc, s.rgb / max(s.a, 1e-6), 1.0 - pow(1.0 - min(s.a, 0.999), voxels_per_step));
        prev = p;
    }
    frag_color = vec4(acc.rgb + (1.0 - acc.a) * u_background, 1.0);
}
