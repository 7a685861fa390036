// The material libraries an OBJ's `mtllib` lines name, read from the OBJ's own folder and
// nowhere else: an OBJ comes from anywhere, and its library could name /dev/zero, a FIFO or
// another user's files. ray takes no material from a library (the scene gives the
// material), but their names decide how usemtl lines group an OBJ's polygons
// (scene/obj_reader.h). One that is missing is passed over, as ever; one outside the folder,
// or not a regular file of a library's size, is refused with the reason (the mesh is
// refused with it).
#pragma once

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <tiny_obj_loader.h>

namespace ray {

class ConfinedMaterialReader : public tinyobj::MaterialReader {
public:
    explicit ConfinedMaterialReader(std::filesystem::path folder) : folder_(std::move(folder)) {}

    bool operator()(const std::string& name, std::vector<tinyobj::material_t>* materials,
                    std::map<std::string, int>* materialMap, std::string* warn, std::string* err) override;

    // Why a library was refused, if one was.
    const std::optional<std::string>& refusal() const { return refusal_; }

private:
    std::filesystem::path folder_;
    std::optional<std::string> refusal_;
};

}  // namespace ray
