#version 330 core
//#INCLUDE clouds.shl
//#INSERT clouds

// Guerrilla's reprojection at the output's size: each frame the reduced buffer traced one pixel of every
// d x d block (u_phase), which is written here exactly; every other pixel keeps what the last frame showed
// there, reprojected through the camera's turn, and falls back to this frame's buffer, bilinear, where the
// last frame has nothing to give (off its edge, or never traced since the view changed).
uniform ivec2 u_size;            // the output's size
uniform int u_down;              // d: the block's edge, r_cloudDownsample
uniform ivec2 u_phase;           // the pixel of each block traced this frame
uniform sampler2D u_fresh;       // this frame's trace: texel b is output pixel b * d + u_phase (nearest)
uniform sampler2D u_fresh_lookups;
uniform sampler2D u_history;     // the last frame's output (linear: a turn reads it between texels)
uniform sampler2D u_history_state;  // its .g: 1 where it held a traced value, 0 where the fallback
uniform int u_history_mode;      // 0 none, 1 the same view (the clock may run), 2 the view turned
uniform vec3 u_prev_forward;     // the last frame's camera basis (mode 2)
uniform vec3 u_prev_right;
uniform vec3 u_prev_up;
uniform int u_clamp;             // the clock moved: kept pixels are clamped to what was traced around them
uniform int u_frames;            // frames since the counts restarted, this one included
uniform int u_rank[16];          // frames after the restart each pixel of a block (x + d y) is first traced
uniform int u_average;           // TAA: a pixel's new sample is averaged with its earlier ones

layout(location = 0) out vec4 out_clouds;
layout(location = 1) out vec4 out_lookups;  // .r this pass's lookups, .g 1 where a traced value is shown

vec4 fresh_at(ivec2 texel) {
    return texelFetch(u_fresh, clamp(texel, ivec2(0), textureSize(u_fresh, 0) - 1), 0);
}

// This frame's buffer at an output pixel: bilinear between the traced pixels around it.
vec4 fallback(ivec2 pixel) {
    vec2 q = vec2(pixel - u_phase) / float(u_down);
    ivec2 b = ivec2(floor(q));
    vec2 f = q - vec2(b);
    return mix(mix(fresh_at(b), fresh_at(b + ivec2(1, 0)), f.x),
               mix(fresh_at(b + ivec2(0, 1)), fresh_at(b + ivec2(1, 1)), f.x), f.y);
}

// Where direction d was in the last frame's output, in pixels; false if off its edge (never read there).
bool last_frame_pixel(vec3 d, out vec2 at) {
    float z = dot(d, u_prev_forward);
    if (z <= 0.0) return false;
    vec2 ndc = vec2(dot(d, u_prev_right) / (u_tan_half_fov * u_aspect), dot(d, u_prev_up) / u_tan_half_fov) / z;
    at = (ndc * 0.5 + 0.5) * vec2(u_size);
    return all(greaterThanEqual(at, vec2(0.5))) && all(lessThanEqual(at, vec2(u_size) - 0.5));
}

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    ivec2 block = pixel / u_down;
    ivec2 offset = pixel - block * u_down;
    bool traced = offset == u_phase;

    vec4 kept = vec4(0.0);
    bool has_kept = false;
    if (u_history_mode == 1) {
        kept = texelFetch(u_history, pixel, 0);
        has_kept = texelFetch(u_history_state, pixel, 0).g > 0.5;
    } else if (u_history_mode == 2) {
        vec2 ndc = (vec2(pixel) + 0.5) / vec2(u_size) * 2.0 - 1.0;
        vec2 at;
        if (last_frame_pixel(ray_dir(ndc), at)) {
            kept = texture(u_history, at / vec2(u_size));
            // a value made only of traced texels: the fallback's blur does not spread by reuse
            has_kept = texture(u_history_state, at / vec2(u_size)).g > 0.999;
        }
    }
    if (has_kept && u_clamp == 1) {  // what the wind moved away does not linger
        ivec2 q = ivec2(floor(vec2(pixel - u_phase) / float(u_down) + 0.5));
        vec4 lo = vec4(1e30), hi = vec4(-1e30);
        for (int y = -1; y <= 1; y++) {
            for (int x = -1; x <= 1; x++) {
                vec4 v = fresh_at(q + ivec2(x, y));
                lo = min(lo, v);
                hi = max(hi, v);
            }
        }
        kept = clamp(kept, lo, hi);
    }

    if (traced) {
        vec4 sample_ = fresh_at(block);
        int rank = u_rank[offset.x + u_down * offset.y];
        int own = (u_frames - 1 - rank) / (u_down * u_down) + 1;  // this pixel's samples since the restart
        float weight = u_average == 1 && has_kept ? max(1.0 / float(own), 1.0 / 16.0) : 1.0;
        out_clouds = mix(kept, sample_, weight);
        out_lookups = vec4(texelFetch(u_fresh_lookups, block, 0).r, 1.0, 0.0, 1.0);
    } else if (has_kept) {
        out_clouds = kept;
        out_lookups = vec4(0.0, 1.0, 0.0, 1.0);
    } else {
        out_clouds = fallback(pixel);
        out_lookups = vec4(0.0, 0.0, 0.0, 1.0);
    }
}
