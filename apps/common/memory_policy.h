#ifndef EULERSPLAT_APPS_COMMON_MEMORY_POLICY_H_
#define EULERSPLAT_APPS_COMMON_MEMORY_POLICY_H_

namespace es {

// glibc's malloc gives a freed block of more than 128 KB back to the
// system (and raises that threshold only as far as the sizes it has seen),
// so a buffer the size of an image, freed and allocated again every frame,
// comes back as fresh pages: a page fault each, which on a virtual
// machine costs microseconds. The stages do that in many places (OpenCV
// temporaries, per-frame metrics, densification), so the apps keep freed
// memory in the process instead: blocks under 32 MB come from the heap and
// the heap is trimmed only past 512 MB of free memory at its top. Measured
// on es_static at 256x192: 14.7 -> 8.4 ms per iteration, its held-out
// evaluations 6x faster (docs/BENCHMARKS.md, "Memory kept by the apps").
// Nothing on other C libraries.
void KeepFreedMemory();

}  // namespace es

#endif  // EULERSPLAT_APPS_COMMON_MEMORY_POLICY_H_
