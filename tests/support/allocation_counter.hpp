// Counting heap allocations in a test program. operator new and Eigen's aligned_malloc both
// go through malloc: in a normal build the test executable interposes glibc's malloc (and so
// sees the plugins' allocations too); under AddressSanitizer, which owns malloc itself, its
// allocation hook counts instead. ThreadSanitizer has no such hook: counting there aborts.
#pragma once

namespace mbd::test {

// True when a probe allocation is counted (the counter sees this build's allocator).
bool allocation_counting_works();
// Allocations made by the calling process while `counting` is on.
class AllocationCount {
public:
    AllocationCount();   // starts counting from zero
    ~AllocationCount();  // stops
    long stop();         // stops and returns the count
private:
    bool running_ = true;
};

}  // namespace mbd::test
