#ifndef EULERSPLAT_APPS_COMMON_THREADS_FLAG_H_
#define EULERSPLAT_APPS_COMMON_THREADS_FLAG_H_

namespace es {

// The threads --threads asks for: N > 0 as given; 0 is OMP_NUM_THREADS when
// the environment sets it (a positive number), else
// std::thread::hardware_concurrency(). Throws InputError naming --threads
// for a negative value.
int ResolvedThreads(int flag, const char* omp_num_threads);

// Applies --threads (every app's flag, defined in threads_flag.cc) to this
// process (omp_set_num_threads) and to the stage binaries it starts
// (OMP_NUM_THREADS), so a driver run with --threads N keeps to N. Returns
// the threads.
int ApplyThreadsFlag();

}  // namespace es

#endif  // EULERSPLAT_APPS_COMMON_THREADS_FLAG_H_
