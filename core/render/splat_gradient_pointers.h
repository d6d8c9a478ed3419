#ifndef EULERSPLAT_CORE_RENDER_SPLAT_GRADIENT_POINTERS_H_
#define EULERSPLAT_CORE_RENDER_SPLAT_GRADIENT_POINTERS_H_

// Where a backward writes (or adds) the gradients of the rendered splat
// arrays, in SplatGradients' layouts (core/render/splat_view.h), in host or
// device memory: written once for the CPU and device gradient structs that
// extend it (LoopModelGradients, DeviceSplatGradients).

namespace es {

struct SplatGradientPointers {
  double* means = nullptr;
  double* log_scales = nullptr;
  double* quats = nullptr;
  double* opacity_logits = nullptr;
  double* sh = nullptr;
};

}  // namespace es

#endif  // EULERSPLAT_CORE_RENDER_SPLAT_GRADIENT_POINTERS_H_
