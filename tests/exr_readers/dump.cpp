// A second and third EXR reader for the export tests: prints an EXR's R, G and B channels as
// the reader returns them, row 0 first. Built twice by tests/export.rs:
//   -DWITH_TINYEXR: TinyEXR's LoadEXR, the loader Godot (and many engines) bundle;
//   -DWITH_OPENEXR: the OpenEXR reference library.
// Output: "W H" on the first line, then one line "R G B" per pixel, row-major, %.9g.
#include <cstdio>
#include <cstdlib>
#include <vector>

#ifdef WITH_TINYEXR
#define TINYEXR_IMPLEMENTATION
#define TINYEXR_USE_MINIZ 0
#include <zlib.h>
#include <tinyexr.h>

int main(int argc, char **argv) {
    if (argc != 2) return 2;
    float *rgba = nullptr;
    int w = 0, h = 0;
    const char *err = nullptr;
    if (LoadEXR(&rgba, &w, &h, argv[1], &err) != TINYEXR_SUCCESS) {
        std::fprintf(stderr, "tinyexr: %s\n", err ? err : "failed");
        return 1;
    }
    std::printf("%d %d\n", w, h);
    for (int k = 0; k < w * h; ++k)
        std::printf("%.9g %.9g %.9g\n", rgba[4 * k], rgba[4 * k + 1], rgba[4 * k + 2]);
    std::free(rgba);
    return 0;
}
#endif

#ifdef WITH_OPENEXR
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>

int main(int argc, char **argv) {
    if (argc != 2) return 2;
    try {
        Imf::InputFile file(argv[1]);
        const Imath::Box2i dw = file.header().dataWindow();
        const int w = dw.max.x - dw.min.x + 1, h = dw.max.y - dw.min.y + 1;
        std::vector<float> c[3];
        Imf::FrameBuffer fb;
        const char *names[3] = {"R", "G", "B"};
        for (int i = 0; i < 3; ++i) {
            c[i].resize(size_t(w) * h);
            char *base = reinterpret_cast<char *>(c[i].data() - dw.min.x - size_t(dw.min.y) * w);
            fb.insert(names[i], Imf::Slice(Imf::FLOAT, base, sizeof(float), sizeof(float) * w));
        }
        file.setFrameBuffer(fb);
        file.readPixels(dw.min.y, dw.max.y);
        std::printf("%d %d\n", w, h);
        for (int k = 0; k < w * h; ++k)
            std::printf("%.9g %.9g %.9g\n", c[0][k], c[1][k], c[2][k]);
    } catch (const std::exception &e) {
        std::fprintf(stderr, "openexr: %s\n", e.what());
        return 1;
    }
    return 0;
}
#endif
