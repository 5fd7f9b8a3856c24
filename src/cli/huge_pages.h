// How glibc's heap is set up for big scenes: transparent huge pages, and a top that is not
// given back to the kernel at every free.
#pragma once

namespace pvrt::cli {

// A scene of a million spheres faults in about 2 GiB of heap, and with 4 KiB pages the
// page faults alone take most of its load and build time. glibc backs its heap with
// transparent huge pages when the tunable glibc.malloc.hugetlb=1 is set, which kernels
// configured for THP "madvise" (Debian's default) need; a tunable is read only at
// start-up, so this sets it and starts the program again, once (execv keeps the process,
// so mpirun and shells see no difference). Nothing happens when it is already set, when
// PVRT_HUGE_PAGES=0, when OpenMP thread binding is asked for (OMP_PROC_BIND, OMP_PLACES,
// GOMP_CPU_AFFINITY: libgomp has pinned the first thread by then), or off glibc and
// Linux; if the restart fails, pvrt goes on as it is.
void restartWithHugePages(char** argv);

// The loader and the build allocate and free hundreds of MB in small blocks (tinyxml2's
// documents, one piece of the file at a time, and the objects' descriptions). glibc gives
// the top of its heap back to the kernel whenever 128 KiB lie free there, and the next
// allocations fault the same amount in again, zeroed by the kernel. Keeping 64 MiB at the
// top (M_TOP_PAD) stops that: the 10^6-sphere scene on one thread with 4 KiB pages took
// 392,493 page faults (1.6 GB zeroed) and 1.50 s of system time before, 237,124 and 0.83 s
// after, at the same peak memory (466 and 461 MiB); with huge pages, 1.01-1.12 s of system
// time before and 0.69-0.90 s after (3 alternating pairs; wall times within the 2-core
// machine's noise). Pages never touched cost nothing, so small scenes do not grow. A
// glibc.malloc.top_pad or trim_threshold the user set stands.
void keepHeapTop();

}  // namespace pvrt::cli
