#include "explain/explanation_report.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <string>

namespace ray {

namespace {

using nlohmann::json;

json vec(const Vec3& v) { return json::array({v.x, v.y, v.z}); }

std::string text(const Vec3& v) {
    std::ostringstream s;
    s << std::setprecision(4) << "(" << v.x << ", " << v.y << ", " << v.z << ")";
    return s.str();
}

std::string number(double value) {
    std::ostringstream s;
    s << std::setprecision(4) << value;
    return s.str();
}

// Motion blur draws a shutter time per sample; in a scene where nothing moves it changes
// nothing, and is not shown.
bool sceneMoves(const Scene& scene) {
    return std::any_of(scene.primitives.begin(), scene.primitives.end(),
                       [](const PrimitiveInstance& p) { return p.motion != Vec3{0, 0, 0}; });
}

// The term of the lighting equation (SPEC §4) a branch's factor is: what its parent
// multiplies the branch's clamped color by. `parent` is the ray whose hit the branch
// leaves from.
std::string factorName(const ExplainedRay& parent, const ExplainedRay& child, const RenderSettings& settings,
                       const Scene& scene) {
    const Material& material = scene.materials[size_t(scene.primitives[size_t(parent.hitInfo.primitive)].material)];
    const bool transparent = settings.refraction && material.transparent != Vec3{};
    const bool fresnel = settings.fresnel && transparent;
    if (transparent && !parent.hitInfo.entering) {
        // Leaving a transparent object: kt·Ot was applied on the way in.
        if (!fresnel) return "1 (kt·Ot was applied on entry)";
        return child.kind == TraceRayKind::Refracted ? "1−R (Fresnel)" : "R (Fresnel)";
    }
    if (child.kind == TraceRayKind::Reflected) return fresnel ? "R·ks·Or" : "ks·Or";
    return fresnel ? "(1−R)·kt·Ot" : "kt·Ot";
}

// JSON has no infinity: a directional light's distance is null.
json distanceJson(double distance) { return std::isfinite(distance) ? json(distance) : json(nullptr); }

json lightJson(const TraceLightTerm& term, const Scene& scene) {
    json j{{"light", term.light},
           {"type", lightTypeName(scene.lights[size_t(term.light)].type)},
           {"to_light", vec(term.toLight)},
           {"distance", distanceJson(term.distance)},
           {"n_dot_l", term.nDotL},
           {"attenuation", term.attenuation},
           {"r_dot_v", term.rDotV},
           {"diffuse", vec(term.diffuse)},
           {"specular", vec(term.specular)},
           {"shadowed", term.shadowed},
           {"contribution", vec(term.contribution)},
           {"unlit", term.unlitReason}};
    if (term.areaCell >= 0) j["area_cell"] = term.areaCell;
    if (term.occluder >= 0) {
        const PrimitiveInstance& occluder = scene.primitives[size_t(term.occluder)];
        j["occluder"] = {{"primitive", term.occluder},
                         {"source", primitiveSource(scene, term.occluder)},
                         {"type", primitiveTypeName(occluder.type)}};
    }
    return j;
}

json rayJson(const ExplainedRay& ray, const Scene& scene, const RenderSettings& settings) {
    json j{{"kind", traceRayKindName(ray.kind)}, {"origin", vec(ray.origin)}, {"direction", vec(ray.direction)},
           {"depth", ray.depth},  {"weight", vec(ray.weight)},          {"factor", vec(ray.factor)},
           {"color", vec(ray.color)}, {"hit", ray.hit}};
    if (!ray.hit) {
        j["stopped"] = "nothing hit";
        return j;
    }
    const TraceHitInfo& hit = ray.hitInfo;
    const PrimitiveInstance& primitive = scene.primitives[size_t(hit.primitive)];
    j["primitive"] = {{"index", hit.primitive},
                      {"source", primitiveSource(scene, hit.primitive)},
                      {"file", scene.sourceFile.string()},
                      {"line", primitive.sourceLine},
                      {"type", primitiveTypeName(primitive.type)},
                      {"material", primitive.material}};
    j["t"] = hit.t;
    j["point"] = vec(hit.point);
    j["normal"] = vec(hit.normal);
    j["entering"] = hit.entering;
    j["uv"] = json::array({hit.uv.u, hit.uv.v});
    j["ambient"] = vec(ray.ambient);
    j["emissive"] = vec(ray.emissive);
    j["diffuse_color"] = vec(ray.diffuseColor);
    if (ray.textured) j["texel"] = vec(ray.texel);
    json lights = json::array();
    for (const TraceLightTerm& term : ray.lights) lights.push_back(lightJson(term, scene));
    j["lights"] = lights;
    json stops = json::array();
    for (const ExplainedStop& stop : ray.stops)
        stops.push_back({{"branch", traceRayKindName(stop.kind)}, {"reason", branchStopName(stop.reason)}});
    j["branches_not_traced"] = stops;
    json children = json::array();
    for (const auto& child : ray.children) {
        json c = rayJson(*child, scene, settings);
        c["factor_name"] = factorName(ray, *child, settings, scene);
        children.push_back(c);
    }
    j["children"] = children;
    return j;
}

void printLight(const TraceLightTerm& term, const Scene& scene, const std::string& indent, std::ostream& out) {
    out << indent << "light " << term.light << " (" << lightTypeName(scene.lights[size_t(term.light)].type);
    if (term.areaCell >= 0) out << ", sample " << term.areaCell;
    out << "): N·L " << number(term.nDotL);
    if (*term.unlitReason) {
        out << ", " << term.unlitReason;
        if (term.occluder >= 0)
            out << " by " << primitiveTypeName(scene.primitives[size_t(term.occluder)].type) << " at "
                << primitiveSource(scene, term.occluder);
        out << "\n";
        return;
    }
    out << ", f_att " << number(term.attenuation) << ", diffuse D·(N·L) " << text(term.diffuse) << ", R·V "
        << number(term.rDotV) << ", specular ks·Os·(R·V)^n " << text(term.specular)
        << " → f_att·I_L·(diffuse + specular) " << text(term.contribution) << "\n";
}

void printRay(const ExplainedRay& ray, const Scene& scene, const RenderSettings& settings, int level,
              std::ostream& out) {
    std::string indent(size_t(level) * 2, ' ');
    out << indent << traceRayKindName(ray.kind) << " ray (depth " << ray.depth << ", weight " << text(ray.weight)
        << ") from " << text(ray.origin) << " along " << text(ray.direction) << "\n";
    indent += "  ";
    if (!ray.hit) {
        out << indent << "nothing hit: background " << text(ray.color) << "\n";
        return;
    }
    const TraceHitInfo& hit = ray.hitInfo;
    const PrimitiveInstance& primitive = scene.primitives[size_t(hit.primitive)];
    out << indent << "hits " << primitiveTypeName(primitive.type) << " at " << primitiveSource(scene, hit.primitive)
        << " (material " << primitive.material << ") t " << number(hit.t) << ", normal " << text(hit.normal) << ", uv ("
        << number(hit.uv.u) << ", " << number(hit.uv.v) << ")" << (hit.entering ? "" : ", from inside") << "\n";
    out << indent << "ambient ka·Oa " << text(ray.ambient) << ", emissive " << text(ray.emissive)
        << ", diffuse color D = kd·Od " << text(ray.diffuseColor);
    if (ray.textured) out << " blended with the texel " << text(ray.texel);
    out << "\n";
    for (const TraceLightTerm& term : ray.lights) printLight(term, scene, indent, out);
    for (const ExplainedStop& stop : ray.stops)
        out << indent << traceRayKindName(stop.kind) << " branch not traced: " << branchStopName(stop.reason) << "\n";
    for (const auto& child : ray.children) {
        out << indent << "+ " << factorName(ray, *child, settings, scene) << " " << text(child->factor)
            << " × the clamped color of:\n";
        printRay(*child, scene, settings, level + 2, out);
    }
    out << indent << "= " << text(ray.color) << "\n";
}

}  // namespace

void printExplanation(const PixelExplanation& e, const Scene& scene, std::ostream& out) {
    out << "pixel (" << e.x << ", " << e.y << ") of " << e.settings.width << "x" << e.settings.height << ", depth "
        << e.settings.maxDepth << ", " << e.samples.size() << " sample" << (e.samples.size() == 1 ? "" : "s") << "\n";
    const bool moves = sceneMoves(scene);
    for (const ExplainedSample& sample : e.samples) {
        out << "sample " << sample.index << " at offset (" << number(sample.sx) << ", " << number(sample.sy) << ")";
        if (moves) out << ", shutter time " << number(sample.time);
        out << ": " << text(sample.color);
        if (!sample.otherLensRays.empty())
            out << ", the mean of " << 1 + sample.otherLensRays.size() << " lens rays' clamped colors";
        out << "\n";
        if (sample.ray) printRay(*sample.ray, scene, e.settings, 1, out);
        for (const auto& lensRay : sample.otherLensRays) printRay(*lensRay, scene, e.settings, 1, out);
    }
    out << "pixel color " << text(e.color) << ", clamped " << text(e.clamped) << ", 8-bit (" << e.bytes[0] << ", "
        << e.bytes[1] << ", " << e.bytes[2] << ")\n";
}

nlohmann::json explanationJson(const PixelExplanation& e, const Scene& scene) {
    const bool moves = sceneMoves(scene);
    json samples = json::array();
    for (const ExplainedSample& sample : e.samples) {
        json s{{"index", sample.index}, {"offset", json::array({sample.sx, sample.sy})},
               {"color", vec(sample.color)}, {"clamped", vec(clamp01(sample.color))}};
        if (moves) s["time"] = sample.time;
        if (sample.ray) s["ray"] = rayJson(*sample.ray, scene, e.settings);
        if (!sample.otherLensRays.empty()) {
            json lensRays = json::array();
            for (const auto& lensRay : sample.otherLensRays) lensRays.push_back(rayJson(*lensRay, scene, e.settings));
            s["other_lens_rays"] = lensRays;
        }
        samples.push_back(s);
    }
    return {{"scene", scene.sourceFile.string()},
            {"pixel", json::array({e.x, e.y})},
            {"width", e.settings.width},
            {"height", e.settings.height},
            {"depth", e.settings.maxDepth},
            {"samples", samples},
            {"color", vec(e.color)},
            {"clamped", vec(e.clamped)},
            {"bytes", json::array({e.bytes[0], e.bytes[1], e.bytes[2]})}};
}

}  // namespace ray
