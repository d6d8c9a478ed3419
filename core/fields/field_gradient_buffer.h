#ifndef EULERSPLAT_CORE_FIELDS_FIELD_GRADIENT_BUFFER_H_
#define EULERSPLAT_CORE_FIELDS_FIELD_GRADIENT_BUFFER_H_

#include <vector>

#include "core/fields/motion_field.h"

namespace es {

// One field's parameter gradients (triplane + MLP) accumulated apart from
// the caller's, e.g. by one thread of a parallel backward pass. Kept all
// zero between uses: AddAndClearGradients adds them to the caller's
// buffers and clears only the triplane chunks that were flagged as written
// (core/fields/gradient_chunks.h), so neither costs a pass over the whole
// triplane.
class FieldGradientBuffer {
 public:
  // Sizes the buffer for a field's blocks (zero-filled; nothing is
  // allocated when it already has these sizes).
  void Resize(int triplane_params, int mlp_params);

  // Accumulators into this buffer, for the blocks `like` has (a nullptr
  // block of `like` stays nullptr), with triplane chunks flagged.
  FieldGradients Gradients(const FieldGradients& like);

 private:
  friend void AddAndClearGradients(
      const std::vector<FieldGradientBuffer*>& buffers,
      const FieldGradients& out);
  std::vector<double> triplane_, mlp_;
  std::vector<char> chunks_;  // per triplane chunk: written since cleared
  bool mlp_written_ = false;
};

// out += every buffer's gradients, added in the order given (so the sum
// does not depend on which thread filled which buffer), and the buffers
// left zero. Blocks of out that are nullptr are not written (the buffers
// then hold nothing for them, see Gradients). out's triplane chunks, when
// it has flags, are flagged where a buffer had a flagged chunk. The
// triplane chunks are summed in parallel (OpenMP).
void AddAndClearGradients(const std::vector<FieldGradientBuffer*>& buffers,
                          const FieldGradients& out);

}  // namespace es

#endif  // EULERSPLAT_CORE_FIELDS_FIELD_GRADIENT_BUFFER_H_
