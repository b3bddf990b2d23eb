// Compile-time dispatch on a mesh's element type: the kernels of elements.cpp and finite_strain.cpp
// are templates on a per-type description (node count, dimension, Gauss points), each file with its
// own; this turns the run-time ElementType into a call with the matching description.
#pragma once

#include "fem/mesh.h"

namespace csim {

// Calls f(Quad4{}), f(Quad8{}) or f(Hexa8{}) for type; throws FemError for an unknown type.
template <class Quad4, class Quad8, class Hexa8, class Function>
decltype(auto) dispatch_element(ElementType type, Function&& f) {
  switch (type) {
    case ElementType::quad4: return f(Quad4{});
    case ElementType::quad8: return f(Quad8{});
    case ElementType::hexa8: return f(Hexa8{});
  }
  throw FemError("unknown element type");
}

}  // namespace csim
