#include "physics/parallel.h"

#include <pthread.h>
#include <sched.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <thread>
#include <vector>

namespace tissu {

namespace {

// How long a waiting thread spins before it sleeps. Explicit steps of the demo hand out
// work every 50-100 us: a short spin catches the other thread's end of share without a
// system call, and a thread whose partner was preempted (by the renderer's threads, say)
// sleeps soon instead of burning the processor the partner needs. Spins of 2 us to 1 ms
// were tried on the demo; 2-8 us lost a third of the speed-up, longer ones were within
// the machine's noise.
constexpr auto kSpin = std::chrono::microseconds(50);

inline void cpu_relax() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#endif
}

// Spins until done() or kSpin has passed; returns done().
template <class Done>
bool spin_until(const Done& done) {
  const auto deadline = std::chrono::steady_clock::now() + kSpin;
  for (int i = 1;; ++i) {
    if (done()) return true;
    cpu_relax();
    if (i % 64 == 0 && std::chrono::steady_clock::now() > deadline) return done();
  }
}

// Helper threads of one calling thread. run() gives share 0 to the caller and share k to
// helper k - 1, and returns when every share is done.
class HelperPool {
 public:
  ~HelperPool() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    wake_.notify_all();
    for (std::thread& t : helpers_) t.join();
  }

  void run(int shares, const std::function<void(int)>& share_body) {
    while (static_cast<int>(helpers_.size()) < shares - 1) {
      // A new helper waits for the next generation, not for one already done.
      const int index = static_cast<int>(helpers_.size());
      const uint64_t current = generation_.load(std::memory_order_relaxed);
      helpers_.emplace_back([this, index, current] { helper_loop(index, current); });
    }
    body_ = &share_body;
    shares_ = shares;
    pending_.store(static_cast<int>(helpers_.size()), std::memory_order_relaxed);
    {
      std::lock_guard<std::mutex> lock(mutex_);
      generation_.fetch_add(1, std::memory_order_release);
    }
    wake_.notify_all();
    share_body(0);
    const auto all_done = [this] { return pending_.load(std::memory_order_acquire) == 0; };
    if (!spin_until(all_done)) {
      std::unique_lock<std::mutex> lock(mutex_);
      done_.wait(lock, all_done);
    }
  }

 private:
  void helper_loop(int index, uint64_t seen) {
    pthread_setname_np(pthread_self(), kSimulationHelperThreadName);
    for (;;) {
      const auto started = [&] { return generation_.load(std::memory_order_acquire) != seen; };
      if (!spin_until(started)) {
        std::unique_lock<std::mutex> lock(mutex_);
        wake_.wait(lock, [&] { return started() || stop_; });
        if (stop_) return;
      }
      seen = generation_.load(std::memory_order_acquire);
      if (index + 1 < shares_) (*body_)(index + 1);
      if (pending_.fetch_sub(1, std::memory_order_acq_rel) == 1) {
        std::lock_guard<std::mutex> lock(mutex_);
        done_.notify_one();
      }
    }
  }

  std::vector<std::thread> helpers_;
  std::mutex mutex_;
  std::condition_variable wake_, done_;
  std::atomic<uint64_t> generation_{0};
  std::atomic<int> pending_{0};
  const std::function<void(int)>* body_ = nullptr;
  int shares_ = 0;
  bool stop_ = false;
};

// First item of share `k` of `shares`: where the cumulative cost reaches k / shares of the
// total (an item goes to the share in which its middle falls), or k / shares of the count.
int share_begin(int k, int shares, int count, const double* cost) {
  if (k <= 0) return 0;
  if (k >= shares) return count;
  if (cost == nullptr) return static_cast<int>(static_cast<long long>(count) * k / shares);
  double total = 0.0;
  for (int i = 0; i < count; ++i) total += cost[i];
  const double target = total * k / shares;
  double before = 0.0;
  int i = 0;
  while (i < count && before + 0.5 * cost[i] < target) before += cost[i++];
  return i;
}

}  // namespace

void parallel_for(int threads, int count, const std::function<void(int)>& body,
                  const double* cost) {
  if (threads <= 1 || count <= 1) {
    for (int i = 0; i < count; ++i) body(i);
    return;
  }
  const int shares = std::min(threads, count);
  thread_local HelperPool pool;
  pool.run(shares, [&](int k) {
    const int end = share_begin(k + 1, shares, count, cost);
    for (int i = share_begin(k, shares, count, cost); i < end; ++i) body(i);
  });
}

int available_processors() {
  cpu_set_t set;
  if (sched_getaffinity(0, sizeof(set), &set) == 0) {
    const int n = CPU_COUNT(&set);
    if (n > 0) return n;
  }
  const unsigned n = std::thread::hardware_concurrency();
  return n > 0 ? static_cast<int>(n) : 1;
}

}  // namespace tissu
