#pragma once
/// \file xdmf_attribute.hpp
/// \brief One XDMF <Attribute> element pointing at a double dataset of an HDF5 file.
#include <fmt/format.h>

#include <string>

namespace biota::io {

/// \brief `<Attribute>` of a Float64 HDF5 dataset. `center` is "Node" or "Cell", `dims` the
/// dataset dimensions as XDMF writes them ("N" or "N 3" ...), `dataset` "file.h5:/group/name".
inline std::string xdmf_attribute(const std::string& name, bool vector, const char* center,
                                  const std::string& dims, const std::string& dataset) {
  return fmt::format(
      "<Attribute Name=\"{}\" AttributeType=\"{}\" Center=\"{}\"><DataItem Format=\"HDF\" "
      "NumberType=\"Float\" Precision=\"8\" Dimensions=\"{}\">{}</DataItem></Attribute>\n",
      name, vector ? "Vector" : "Scalar", center, dims, dataset);
}

}  // namespace biota::io
