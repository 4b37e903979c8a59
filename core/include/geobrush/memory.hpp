// Process-wide allocator settings for interactive editing.
#pragma once

namespace geobrush {

// Keeps freed blocks of up to 32 MiB in the heap for reuse instead of returning them to the
// kernel. Every dab builds a result mesh of tens of megabytes and frees the previous one; by
// default glibc unmaps such blocks, and the next mesh pays a page fault for every 4 KiB it
// touches again: half of the stitch's time on a 168k-vertex target. Hosts call this once at
// start-up (the CLI and the benchmarks do); it changes no result. Returns false where the C
// library does not support the settings.
bool reuseFreedMemory();

}  // namespace geobrush
