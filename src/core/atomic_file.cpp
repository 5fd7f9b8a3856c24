#include "core/atomic_file.h"

#include "core/output_files.h"

namespace pvrt {

void writeFileAtomically(const std::string& path, const std::string& bytes) {
  OutputFiles out;
  out.output(path, "the output");
  out.stageBytes(path, bytes);
  out.commit();
}

}  // namespace pvrt
