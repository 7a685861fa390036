#include "scene/scene.h"

namespace ray {

const char* primitiveTypeName(PrimitiveType type) {
    switch (type) {
        case PrimitiveType::Cube: return "cube";
        case PrimitiveType::Sphere: return "sphere";
        case PrimitiveType::Cylinder: return "cylinder";
        case PrimitiveType::Cone: return "cone";
        case PrimitiveType::Torus: return "torus";
        case PrimitiveType::Mesh: return "mesh";
        case PrimitiveType::Csg: return "csg";
    }
    return "unknown";
}

}  // namespace ray
