#include "app/signals.h"

#include <atomic>
#include <csignal>
#include <unistd.h>

namespace tissu {

namespace {
// Signal handlers can only reach process-wide state.
std::atomic<int> g_interrupts{0};

void on_signal(int) {
  if (g_interrupts.fetch_add(1) >= 1) _exit(130);
  static const char kMessage[] = "tissu: interrupted; finishing the current frame (again to abort)\n";
  const ssize_t ignored = write(STDERR_FILENO, kMessage, sizeof(kMessage) - 1);
  (void)ignored;
}
}  // namespace

void install_interrupt_handlers() {
  struct sigaction action {};
  action.sa_handler = on_signal;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

bool interrupt_requested() { return g_interrupts.load() > 0; }

}  // namespace tissu
