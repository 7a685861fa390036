#include "explain/pixel_explanation.h"

#include <algorithm>

#include "image/image.h"
#include "reference/reference_renderer.h"

namespace ray {

namespace {

// Builds the tree from the renderer's reports: rays nest, so a stack of open rays suffices.
class TreeRecorder : public TraceObserver {
public:
    explicit TreeRecorder(std::vector<ExplainedSample>& samples) : samples_(samples) {}

    void beginSample(int k, double sx, double sy, double time) override {
        ExplainedSample& sample = samples_.emplace_back();
        sample.index = k;
        sample.sx = sx;
        sample.sy = sy;
        sample.time = time;
    }
    void endSample(const Vec3& color) override { samples_.back().color = color; }

    void beginRay(TraceRayKind kind, const Vec3& origin, const Vec3& direction, int depth, const Vec3& weight,
                  const Vec3& factor) override {
        auto ray = std::make_unique<ExplainedRay>();
        ray->kind = kind;
        ray->origin = origin;
        ray->direction = direction;
        ray->depth = depth;
        ray->weight = weight;
        ray->factor = factor;
        ExplainedRay* raw = ray.get();
        ExplainedSample& sample = samples_.back();
        if (!open_.empty()) open_.back()->children.push_back(std::move(ray));
        else if (sample.ray) sample.otherLensRays.push_back(std::move(ray));  // the course's lens grid
        else sample.ray = std::move(ray);
        open_.push_back(raw);
    }
    void miss() override { open_.back()->hit = false; }
    void hit(const TraceHitInfo& hit) override {
        open_.back()->hit = true;
        open_.back()->hitInfo = hit;
    }
    void surfaceTerms(const Vec3& ambient, const Vec3& emissive, const Vec3& diffuseColor, bool textured,
                      const Vec3& texel) override {
        ExplainedRay& ray = *open_.back();
        ray.ambient = ambient;
        ray.emissive = emissive;
        ray.diffuseColor = diffuseColor;
        ray.textured = textured;
        ray.texel = texel;
    }
    void lightTerm(const TraceLightTerm& term) override { open_.back()->lights.push_back(term); }
    void branchStopped(TraceRayKind kind, BranchStop reason) override { open_.back()->stops.push_back({kind, reason}); }
    void endRay(const Vec3& color) override {
        open_.back()->color = color;
        open_.pop_back();
    }

private:
    std::vector<ExplainedSample>& samples_;
    std::vector<ExplainedRay*> open_;
};

}  // namespace

PixelExplanation explainPixel(const Scene& scene, const RenderSettings& settings, int x, int y) {
    PixelExplanation explanation;
    explanation.x = x;
    explanation.y = y;
    explanation.settings = settings;
    TreeRecorder recorder(explanation.samples);
    Vec3 color = renderReferencePixel(scene, settings, x, y, &recorder);
    // The image stores floats (Image::set): the explanation reports the pixel exactly as
    // it is stored. (Written out per channel: GCC 12 at -O3 dropped the float rounding of
    // x and y when this went through a one-pixel Image.)
    volatile float red = float(color.x), green = float(color.y), blue = float(color.z);
    explanation.color = {red, green, blue};
    explanation.clamped = clamp01(explanation.color);
    explanation.bytes = {quantize8(explanation.color.x), quantize8(explanation.color.y), quantize8(explanation.color.z)};
    return explanation;
}

std::string primitiveSource(const Scene& scene, int primitive) {
    if (primitive < 0 || size_t(primitive) >= scene.primitives.size()) return "?";
    return scene.sourceFile.filename().string() + ":" + std::to_string(scene.primitives[size_t(primitive)].sourceLine);
}

}  // namespace ray
