#include "edit/struct_fields.h"

namespace ray::edit {

namespace {

// The inputs of `owner`'s member fields that `keep` accepts, read from `value`.
template <class Value, class Keep>
std::vector<FieldInput> memberFields(FieldOwner owner, const Value& value, Keep keep) {
    std::vector<FieldInput> inputs;
    for (const EditField* field : fieldsOf(owner)) {
        if (!keep(*field)) continue;
        std::visit(
            [&](auto member) {
                using M = decltype(member);
                if constexpr (std::is_same_v<M, Vec3 Value::*> || std::is_same_v<M, double Value::*>)
                    inputs.push_back({field, FieldValue(value.*member), {}});
            },
            field->member);
    }
    return inputs;
}

bool every(const EditField&) { return true; }

}  // namespace

std::vector<FieldInput> cameraFields(const Camera& camera) { return memberFields(FieldOwner::Camera, camera, every); }

std::vector<FieldInput> globalsFields(const GlobalCoefficients& globals) {
    return memberFields(FieldOwner::Globals, globals, every);
}

std::vector<FieldInput> lightFields(const Light& light, bool all) {
    std::vector<FieldInput> inputs{{findField(FieldOwner::Light, "type"), std::string(lightTypeName(light.type)), {}}};
    for (FieldInput& input :
         memberFields(FieldOwner::Light, light, [&](const EditField& field) { return all || field.appliesTo(light.type); }))
        inputs.push_back(std::move(input));
    return inputs;
}

std::vector<FieldInput> materialFields(const Material& material, bool textures) {
    std::vector<FieldInput> inputs = memberFields(FieldOwner::Object, material, every);
    if (!textures) return inputs;
    for (const EditField* field : fieldsOf(FieldOwner::Object)) {
        const bool bump = field->group == "bump map";
        const TextureMap& map = bump ? material.bumpMap : material.texture;
        switch (field->special) {
            case SpecialField::Texture:
            case SpecialField::BumpMap:
                inputs.push_back({field, map.image >= 0 ? FieldValue(ImageHandle{map.image}) : FieldValue(std::string()), {}});
                break;
            case SpecialField::TextureU:
            case SpecialField::BumpMapU: inputs.push_back({field, map.repeatU, {}}); break;
            case SpecialField::TextureV:
            case SpecialField::BumpMapV: inputs.push_back({field, map.repeatV, {}}); break;
            default: break;
        }
    }
    return inputs;
}

}  // namespace ray::edit
