// SIGINT / SIGTERM: the first one asks the run to stop after the current frame (the video
// is closed properly, the report says "interrupted"); a second one exits at once with 130.
#pragma once

namespace tissu {

void install_interrupt_handlers();
bool interrupt_requested();

}  // namespace tissu
