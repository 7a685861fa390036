// render_scene <scene.xml> <out.png>: loads a scene with ray's installed API and renders it
// small on the reference renderer (no OpenCL needed).
#include <iostream>

#include <ray/ray.h>

int main(int argc, char** argv) {
    if (argc != 3) {
        std::cerr << "usage: render_scene <scene.xml> <out.png>\n";
        return 2;
    }
    try {
        ray::api::LoadResult loaded = ray::api::Scene::load(argv[1]);
        ray::api::Renderer renderer(loaded.scene, "ref");
        ray::api::Settings settings;
        settings.width = 48;
        settings.height = 36;
        renderer.setSettings(settings);
        ray::api::FrameStats stats;
        std::vector<float> rgb = renderer.render(&stats);
        ray::api::saveImage(rgb, settings.width, settings.height, argv[2]);
        std::cout << "rendered " << stats.primaryRays << " primary rays on " << stats.device << "\n";
        return 0;
    } catch (const ray::api::InputError& e) {
        std::cerr << e.what() << "\n";
        return 2;
    } catch (const ray::api::Error& e) {
        std::cerr << e.what() << "\n";
        return 3;
    }
}
