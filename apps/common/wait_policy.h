#ifndef EULERSPLAT_APPS_COMMON_WAIT_POLICY_H_
#define EULERSPLAT_APPS_COMMON_WAIT_POLICY_H_

#include <functional>
#include <string>

namespace es {

// OpenMP's idle threads spin for a long while (libgomp: 300k spins) before
// they sleep. On a machine whose cores are busy with other jobs the spin
// steals those cores: es_train's 100 iterations cost 2.3x the CPU seconds
// with 2 threads on 2 contested cores (docs/BENCHMARKS.md, "A shared
// machine"). kSpinCount spins, then a futex sleep, costs little on an idle
// machine and barely more than the work on a busy one.
inline constexpr const char* kSpinCount = "10000";
// Set by ApplyWaitPolicy before it re-executes, so the new process never
// re-executes again, even if the policy could not be set.
inline constexpr const char* kWaitPolicyMarker = "ES_WAIT_POLICY_APPLIED";

// True when the app should set the policy itself: the user set neither
// OMP_WAIT_POLICY nor GOMP_SPINCOUNT (nullptr: unset), and the marker says
// this process is not the re-executed one already.
bool WaitPolicyNeeded(const char* omp_wait_policy, const char* gomp_spincount,
                      const char* marker);

// The policy this process runs with, for --v=1: "GOMP_SPINCOUNT=10000,
// set by the app", "OMP_WAIT_POLICY=active, the user's", or libgomp's
// default (when the app could not set its own).
std::string WaitPolicyDescription(const char* omp_wait_policy,
                                  const char* gomp_spincount,
                                  const char* marker);

// Runs the new process image with `argv`; returns only on failure.
using ExecFunction = std::function<void(char** argv)>;

// libgomp reads its wait policy once, when the program loads, so setting
// it means starting again: when WaitPolicyNeeded says so for this
// process' environment, sets GOMP_SPINCOUNT=kSpinCount and the marker,
// then re-executes the program (`exec`, default /proc/self/exe) with the
// same arguments. Returns (having changed nothing the user sees) when the
// policy is not needed or the exec failed. Call first thing in main, before
// any thread starts or output is buffered.
void ApplyWaitPolicy(char** argv, const ExecFunction& exec = nullptr);

}  // namespace es

#endif  // EULERSPLAT_APPS_COMMON_WAIT_POLICY_H_
