// Transparent huge pages for the heap, which big scenes need for a fast start.
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

}  // namespace pvrt::cli
