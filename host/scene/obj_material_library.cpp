#include "scene/obj_material_library.h"

#include <sstream>

#include "core/input_file.h"

namespace ray {

namespace {

// A material library is a few lines a material.
constexpr InputLimit kMaterialLibraryLimit{"a material library (mtllib)", uint64_t(16) << 20,
                                           "the text of thousands of materials"};

}  // namespace

bool ConfinedMaterialReader::operator()(const std::string& name, std::vector<tinyobj::material_t>* materials,
                                        std::map<std::string, int>* materialMap, std::string* warn,
                                        std::string* err) {
    if (refusal_) return false;
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::path folder = fs::weakly_canonical(folder_, ec);
    const fs::path candidate = folder_ / fs::path(name);
    const fs::path real = fs::weakly_canonical(candidate, ec);
    const fs::path inside = real.lexically_relative(folder);
    if (fs::path(name).is_absolute() || ec || inside.empty() || *inside.begin() == "..") {
        refusal_ = "mtllib '" + name + "' is outside the OBJ's folder; ray reads a material library only from the " +
                   "OBJ's own folder (and uses none of its materials): remove the mtllib line or move the file";
        return false;
    }
    if (!fs::exists(fs::symlink_status(candidate, ec))) return false;  // missing: no materials, as ever
    try {
        std::istringstream text(readInputFile(candidate, kMaterialLibraryLimit));
        tinyobj::LoadMtl(materialMap, materials, &text, warn, err);
    } catch (const InputFileError& e) {
        refusal_ = "mtllib '" + name + "' (" + candidate.string() + "): " + e.reason();
        return false;
    }
    return true;
}

}  // namespace ray
