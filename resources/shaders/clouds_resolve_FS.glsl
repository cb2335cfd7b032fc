#version 330 core
//#INCLUDE clouds.shl
//#INSERT clouds
//#INCLUDE clouds_upsample.shl
//#INSERT clouds_upsample

// Guerrilla's reprojection at the picture's size (the output's; half of it at a drag's cheapest level): each frame
// the reduced buffer traced one pixel of every d x d block (u_phase), which is written here exactly; every other
// pixel keeps what the last frame showed where its clouds were then (through the camera's turn and the wind's
// motion at the clouds' depth), and falls back to this frame's buffer where the last frame has nothing to give
// (off its edge, or never traced since the view changed). Both are read only from texels whose rays end where this
// pixel's does (clouds_upsample.shl).
uniform ivec2 u_size;            // the reprojected picture's size
uniform ivec2 u_history_size;    // the last one's (a drag's cheapest level draws a smaller one)
uniform int u_down;              // d: the block's edge, r_cloudDownsample
uniform ivec2 u_phase;           // the pixel of each block traced this frame
uniform sampler2D u_fresh;       // this frame's trace: texel b is picture pixel b * d + u_phase
uniform sampler2D u_fresh_state; // its state
uniform sampler2D u_history;     // the last frame's output
uniform sampler2D u_history_state;  // its state
uniform int u_history_mode;      // 0 none, 1 the same view (the clock may run), 2 the view turned
uniform vec3 u_prev_forward;     // the last frame's camera basis
uniform vec3 u_prev_right;
uniform vec3 u_prev_up;
uniform vec3 u_motion;           // how far the clouds moved since the last frame, metres (the wind)
uniform int u_clock_moved;       // kept pixels follow u_motion and are clamped to what was traced around them
uniform int u_frames;            // frames since the counts restarted, this one included
uniform int u_rank[64];          // frames after the restart each pixel of a block (x + d y) is first traced
uniform int u_average;           // TAA: a pixel's new sample is averaged with its earlier ones
uniform int u_prior;             // samples the kept values stand for when the counts restarted
uniform float u_min_weight;      // a new sample's least weight (while the clock runs: old ones fade)

layout(location = 0) out vec4 out_clouds;
layout(location = 1) out vec4 out_state;  // the state (clouds_upsample.shl); .r this pass's lookups

vec4 fresh_at(ivec2 texel) {
    return texelFetch(u_fresh, clamp(texel, ivec2(0), textureSize(u_fresh, 0) - 1), 0);
}

// Where direction d was in the last frame's output, in pixels; false if off its picture (never read there: the
// strips the renderer traces after a turn, reprojection.py's new_directions, hold what is).
bool last_frame_pixel(vec3 d, out vec2 at) {
    float z = dot(d, u_prev_forward);
    if (z <= 0.0) return false;
    vec2 ndc = vec2(dot(d, u_prev_right) / (u_tan_half_fov * u_aspect), dot(d, u_prev_up) / u_tan_half_fov) / z;
    at = (ndc * 0.5 + 0.5) * vec2(u_history_size);
    return all(greaterThanEqual(at, vec2(0.0))) && all(lessThanEqual(at, vec2(u_history_size)));
}

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    ivec2 block = pixel / u_down;
    ivec2 offset = pixel - block * u_down;
    bool traced = offset == u_phase;
    vec3 d = ray_dir((vec2(pixel) + 0.5) / vec2(u_size) * 2.0 - 1.0);
    float ground = ground_ray(u_camera, d) ? 1.0 : 0.0;
    vec4 fresh_state = texelFetch(u_fresh_state, block, 0);  // of this pixel's block (traced: its own)
    float lookups_here = traced ? fresh_state.r : 0.0;
    float t0, t1;
    if (!cloud_segment(u_camera, d, t0, t1)) {  // no clouds on this ray, as the trace would say
        out_clouds = vec4(0.0);
        out_state = vec4(lookups_here, 1.0, ground, MAX_MARCH);
        return;
    }

    // where the last frame saw what this pixel shows: this very pixel for the same view of still clouds; else
    // where the turn puts this direction and, where the wind moved the clouds, where they were then at the depth
    // the last frame held for them there
    vec4 kept = vec4(0.0), kept_state = vec4(0.0);
    bool has_kept = false;
    if (u_history_mode != 0) {
        vec2 at = vec2(pixel) + 0.5;
        bool seen = true;
        if (u_history_mode == 2 || u_clock_moved == 1 || u_history_size != u_size) {
            seen = last_frame_pixel(d, at);
            if (seen && u_clock_moved == 1) {
                float depth = texelFetch(u_history_state, min(ivec2(at), u_history_size - 1), 0).a;
                seen = last_frame_pixel(last_direction(d, depth, u_motion), at);
            }
        }
        if (seen) {
            // only traced texels (the fallback's blur does not spread by reuse) on this side of the horizon
            float weight;
            kept = resample(u_history, u_history_state, at - 0.5, ground, kept_state, weight);
            has_kept = weight > 0.0;
        }
    }
    if (has_kept && u_clock_moved == 1) {  // what the wind changed (beyond its motion) does not linger
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
        int own = (u_frames - 1 - rank) / (u_down * u_down) + 1 + u_prior;  // the samples this pixel stands for
        float share = u_average == 1 && has_kept ? max(1.0 / float(own), u_min_weight) : 1.0;
        out_clouds = mix(kept, sample_, share);
        out_state = vec4(lookups_here, 1.0, ground, fresh_state.a);
    } else if (has_kept) {
        out_clouds = kept;
        out_state = vec4(0.0, 1.0, ground, kept_state.a);
    } else {  // this frame's buffer, from the traced pixels around on this side of the horizon
        float weight;
        out_clouds = upsample(u_fresh, u_fresh_state, vec2(pixel - u_phase) / float(u_down), ground, false,
                              fresh_state, weight);
        out_state = vec4(0.0, 0.0, ground, fresh_state.a);
    }
}
