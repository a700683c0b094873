// bmCTFileTypes.h - the file types the CT import reads itself (bmCTReader.h), for its messages
// and for the file dialogs that offer them. VTK image files (.vti, .vtk) are read through VTK
// (Logic/VTK/Module/bmVTKImageVolume.h VTKImageExtensions). ITK-free.
#pragma once

#include <string>
#include <vector>

namespace bm {

/// The CT files bmCTReader reads, lower case with the dot: NRRD (.nrrd, .nhdr), MetaImage (.mha,
/// .mhd), NIfTI (.nii, .nii.gz), a DICOM file (.dcm; a folder is read as a DICOM series) and an
/// InVesalius project (.inv3).
const std::vector<std::string>& CTFileExtensions();

/// "a, b, c or d" of the extensions (an error message's list).
std::string ExtensionList(const std::vector<std::string>& extensions);

} // namespace bm
