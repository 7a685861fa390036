#include "scene/scene.h"

#include "shared_types.h"  // the torus radii, for its bounds

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

const char* lightTypeName(LightType type) {
    switch (type) {
        case LightType::Point: return "point";
        case LightType::Directional: return "directional";
        case LightType::Spot: return "spot";
        case LightType::Area: return "area";
    }
    return "point";
}

void fitObjectBox(PrimitiveInstance& instance, const std::vector<TriangleMesh>& meshes) {
    if (instance.type == PrimitiveType::Torus) {
        constexpr double ringRadius = RAY_TORUS_MAJOR_RADIUS, tubeRadius = RAY_TORUS_MINOR_RADIUS;
        instance.objectLo = {-ringRadius - tubeRadius, -tubeRadius, -ringRadius - tubeRadius};
        instance.objectHi = -1 * instance.objectLo;
    } else if (instance.type == PrimitiveType::Mesh) {
        instance.objectLo = meshes[size_t(instance.mesh)].boundsLo;
        instance.objectHi = meshes[size_t(instance.mesh)].boundsHi;
    } else {
        instance.objectLo = {-0.5, -0.5, -0.5};
        instance.objectHi = {0.5, 0.5, 0.5};
    }
}

}  // namespace ray
