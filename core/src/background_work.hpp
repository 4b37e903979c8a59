// Work that no one waits for, done ahead of need on a thread of the library's own.
#pragma once

#include <functional>

namespace geobrush {

// Runs `work` on the library's background thread after the piece under way there, in place of
// any piece still waiting for its turn: the pieces run one at a time, the newest posted next, so
// work done ahead of need takes the memory of one piece at most. Without a thread to be had it is
// left undone. The thread is joined at exit; a piece waiting then is dropped.
void postBackgroundWork(std::function<void()> work);

}  // namespace geobrush
