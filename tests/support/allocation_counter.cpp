#include "support/allocation_counter.hpp"

#include <atomic>
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <execinfo.h>

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define MBD_TEST_SANITIZER_MALLOC 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
#define MBD_TEST_SANITIZER_MALLOC 1
#endif
#endif
#if defined(__SANITIZE_THREAD__)
#define MBD_TEST_TSAN 1
#elif defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define MBD_TEST_TSAN 1
#endif
#endif

namespace {
std::atomic<bool> g_counting{false};
std::atomic<long> g_count{0};
thread_local bool t_tracing = false;
void count_malloc() {
    if (!g_counting.load(std::memory_order_relaxed)) return;
    g_count.fetch_add(1, std::memory_order_relaxed);
    // MBD_TRACE_ALLOCATIONS=1: the call stack of every counted allocation on stderr
    static const bool trace = std::getenv("MBD_TRACE_ALLOCATIONS") != nullptr;
    if (trace && !t_tracing) {
        t_tracing = true;
        void* frames[12];
        const int n = backtrace(frames, 12);
        backtrace_symbols_fd(frames, n, 2);
        std::fputs("----\n", stderr);
        t_tracing = false;
    }
}
}  // namespace

#if defined(MBD_TEST_TSAN)
// ThreadSanitizer owns malloc and its hook would count every thread's allocations.
#elif defined(MBD_TEST_SANITIZER_MALLOC)
// the sanitizer runtime's allocator interface (sanitizer/allocator_interface.h, which g++ does not ship)
extern "C" int __sanitizer_install_malloc_and_free_hooks(void (*)(const volatile void*, std::size_t),
                                                         void (*)(const volatile void*));
namespace {
void sanitizer_malloc_hook(const volatile void*, std::size_t) { count_malloc(); }
[[maybe_unused]] const int g_hook_installed = __sanitizer_install_malloc_and_free_hooks(sanitizer_malloc_hook, nullptr);
}  // namespace
#else
extern "C" void* __libc_malloc(std::size_t size);
extern "C" void* malloc(std::size_t size) {
    count_malloc();
    return __libc_malloc(size);
}
#endif

namespace mbd::test {

bool allocation_counting_works() {
    AllocationCount count;
    void* volatile probe = std::malloc(64);
    std::free(probe);
    return count.stop() > 0;
}

AllocationCount::AllocationCount() {
#if defined(MBD_TEST_TSAN)
    std::fprintf(stderr, "allocation counting is not available under ThreadSanitizer\n");
    std::abort();
#endif
    g_count = 0;
    g_counting = true;
}

AllocationCount::~AllocationCount() { g_counting = false; }

long AllocationCount::stop() {
    g_counting = false;
    running_ = false;
    return g_count.load();
}

}  // namespace mbd::test
