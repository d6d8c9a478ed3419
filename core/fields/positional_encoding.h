#ifndef EULERSPLAT_CORE_FIELDS_POSITIONAL_ENCODING_H_
#define EULERSPLAT_CORE_FIELDS_POSITIONAL_ENCODING_H_

namespace es {

// Sinusoidal encoding of a scalar: for k = 0 .. num_frequencies - 1 writes
//   out[2k] = sin(2 pi 2^k value / period), out[2k+1] = cos(...),
// so the lowest frequency has period `period` and each next one half of it.
// Writes 2 * num_frequencies values.
void EncodeSinusoidal(double value, int num_frequencies, double period,
                      double* out);

}  // namespace es

#endif  // EULERSPLAT_CORE_FIELDS_POSITIONAL_ENCODING_H_
