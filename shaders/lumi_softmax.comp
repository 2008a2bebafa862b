#version 460
#extension GL_GOOGLE_include_directive : require
// Lumi-Net's output: per pixel, a softmax of the views' weight logits over the views that see it,
// and alpha, the logistic of the mean of their alpha logits. Written so that no input gives a NaN:
// a NaN or -Inf logit takes the view out of the softmax (+Inf counts as RT_LUMI_MAX_LOGIT, so ties
// share); when every seeing view is out, they share equally (the network says nothing, the views
// still see the point); a NaN alpha logit, or a mean of +Inf and -Inf, gives alpha 0; no view
// seeing the pixel gives weights 0 and alpha 0.
#include "shared/config.h"
#include "shared/lumi_net.h"
#include "common/lumi_numeric.glsl"

layout(local_size_x = RT_TILE_X, local_size_y = RT_TILE_Y) in;

layout(std430, binding = 0) readonly buffer Logits { float logits[]; };      // (views, 2, h, w)
layout(std430, binding = 1) readonly buffer Coverage { float coverage[]; };  // (views, 1, h, w)
layout(std430, binding = 2) writeonly buffer Blending { float blending[]; }; // (1, 1 + views, h, w)
layout(push_constant) uniform Push { LumiTensorParams params; };

void main() {
  const ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (pixel.x >= int(params.width) || pixel.y >= int(params.height)) return;
  const int plane = int(params.width * params.height), at = pixel.y * int(params.width) + pixel.x;
  const int views = int(params.views);
  float logit[RT_IBR_MAX_VIEWS];
  bool counted[RT_IBR_MAX_VIEWS];
  int seeing = 0, in_softmax = 0;
  float largest = 0.0, alpha_sum = 0.0;
  int alpha_terms = 0;
  for (int v = 0; v < RT_IBR_MAX_VIEWS; ++v) {
    counted[v] = false;
    logit[v] = 0.0;
    if (v >= views || !(coverage[v * plane + at] > 0.0)) continue;
    ++seeing;
    const float alpha_logit = logits[(v * RT_LUMI_HEAD_CHANNELS + 1) * plane + at];
    if (!is_nan(alpha_logit)) {
      alpha_sum += alpha_logit;
      ++alpha_terms;
    }
    const float l = logits[(v * RT_LUMI_HEAD_CHANNELS) * plane + at];
    if (is_nan(l) || is_negative_infinity(l)) continue;
    logit[v] = min(l, RT_LUMI_MAX_LOGIT);
    largest = in_softmax == 0 ? logit[v] : max(largest, logit[v]);
    counted[v] = true;
    ++in_softmax;
  }
  float weight[RT_IBR_MAX_VIEWS];
  float sum = 0.0;
  for (int v = 0; v < RT_IBR_MAX_VIEWS; ++v) {
    const bool sees = v < views && coverage[v * plane + at] > 0.0;
    weight[v] = in_softmax > 0 ? (counted[v] ? exp(logit[v] - largest) : 0.0) : (sees ? 1.0 : 0.0);
    sum += weight[v];
  }
  float alpha = 0.0;
  if (seeing > 0 && alpha_terms > 0) {
    const float mean = alpha_sum / float(alpha_terms);
    alpha = is_nan(mean) ? 0.0 : safe_sigmoid(mean);
  }
  blending[at] = alpha;
  for (int v = 0; v < views; ++v) blending[(1 + v) * plane + at] = sum > 0.0 ? weight[v] / sum : 0.0;
}
