#include "physics/parallel.h"

#include <pthread.h>
#include <sched.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <memory>
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

// Spins until done() or kSpin has passed; returns done(). Yields the processor now and
// then, so that a thread it waits for can run when there are more threads than cores.
template <class Done>
bool spin_until(const Done& done) {
  const auto deadline = std::chrono::steady_clock::now() + kSpin;
  for (int i = 1;; ++i) {
    if (done()) return true;
    cpu_relax();
    if (i % 64 == 0) {
      if (std::chrono::steady_clock::now() > deadline) return done();
      sched_yield();
    }
  }
}

// Helper threads of one calling thread. run(shares, body) gives share 0 to the caller and
// share k to helper k - 1, and returns when every share is done. Only the helpers that
// take part are woken and waited for.
class HelperPool {
 public:
  ~HelperPool() {
    if (owner_ != getpid()) {  // a forked child: the helpers are the parent's
      for (auto& helper : helpers_) helper->thread.detach();
      return;
    }
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    for (auto& helper : helpers_) helper->wake.notify_one();
    for (auto& helper : helpers_) helper->thread.join();
  }

  // False in a forked child, whose copy of the pool has no threads.
  bool usable() const { return owner_ == getpid(); }

  void run(int shares, const std::function<void(int)>& share_body) {
    while (static_cast<int>(helpers_.size()) < shares - 1) {
      helpers_.push_back(std::make_unique<Helper>());
      Helper* helper = helpers_.back().get();
      const int index = static_cast<int>(helpers_.size()) - 1;
      helper->thread = std::thread([this, helper, index] { helper_loop(*helper, index); });
    }
    body_ = &share_body;
    pending_.store(shares - 1, std::memory_order_relaxed);
    ++generation_;
    for (int k = 0; k < shares - 1; ++k) {
      Helper& helper = *helpers_[k];
      {
        std::lock_guard<std::mutex> lock(mutex_);
        helper.go.store(generation_, std::memory_order_release);
      }
      helper.wake.notify_one();
    }
    share_body(0);
    const auto all_done = [this] { return pending_.load(std::memory_order_acquire) == 0; };
    if (!spin_until(all_done)) {
      std::unique_lock<std::mutex> lock(mutex_);
      done_.wait(lock, all_done);
    }
  }

 private:
  struct Helper {
    std::atomic<uint64_t> go{0};  // the generation it was last asked to run
    std::condition_variable wake;
    std::thread thread;
  };

  void helper_loop(Helper& helper, int index) {
    pthread_setname_np(pthread_self(), kSimulationHelperThreadName);
    uint64_t seen = 0;  // go starts at 0 and is only raised after this thread exists
    for (;;) {
      const auto asked = [&] { return helper.go.load(std::memory_order_acquire) != seen; };
      if (!spin_until(asked)) {
        std::unique_lock<std::mutex> lock(mutex_);
        helper.wake.wait(lock, [&] { return asked() || stop_; });
        if (!asked()) return;  // stopping
      }
      seen = helper.go.load(std::memory_order_acquire);
      (*body_)(index + 1);
      if (pending_.fetch_sub(1, std::memory_order_acq_rel) == 1) {
        std::lock_guard<std::mutex> lock(mutex_);
        done_.notify_one();
      }
    }
  }

  const pid_t owner_ = getpid();
  std::vector<std::unique_ptr<Helper>> helpers_;
  std::mutex mutex_;
  std::condition_variable done_;
  uint64_t generation_ = 0;  // written by the calling thread only
  std::atomic<int> pending_{0};
  const std::function<void(int)>* body_ = nullptr;
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
  // Calls from inside a share (nested) run on their thread, as do calls in a forked child.
  thread_local bool inside_share = false;
  thread_local HelperPool pool;
  if (threads <= 1 || count <= 1 || inside_share || !pool.usable()) {
    for (int i = 0; i < count; ++i) body(i);
    return;
  }
  const int shares = std::min(threads, count);
  // noexcept: a throwing body ends the program rather than leaving helpers running on a
  // finished call.
  pool.run(shares, [&](int k) noexcept {
    inside_share = true;
    const int end = share_begin(k + 1, shares, count, cost);
    for (int i = share_begin(k, shares, count, cost); i < end; ++i) body(i);
    inside_share = false;
  });
}

void parallel_for_ranges(int threads, int count, int per_range,
                         const std::function<void(int, int)>& body) {
  const int ranges = (count + per_range - 1) / per_range;
  parallel_for(threads, ranges, [&](int r) {
    body(r * per_range, std::min(count, (r + 1) * per_range));
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
