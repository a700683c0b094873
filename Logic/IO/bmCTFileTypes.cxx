// bmCTFileTypes.cxx - see bmCTFileTypes.h.
#include "bmCTFileTypes.h"

namespace bm {

const std::vector<std::string>& CTFileExtensions() {
  static const std::vector<std::string> kExtensions{".nrrd", ".nhdr",   ".mha", ".mhd",
                                                    ".nii",  ".nii.gz", ".dcm", ".inv3"};
  return kExtensions;
}

std::string ExtensionList(const std::vector<std::string>& extensions) {
  std::string s;
  for (size_t i = 0; i < extensions.size(); ++i)
    s += (i == 0 ? "" : i + 1 == extensions.size() ? " or " : ", ") + extensions[i];
  return s;
}

} // namespace bm
