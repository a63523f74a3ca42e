// richdem_pits.cpp - times RichDEM's pit removal on a float EXR, for bench/richdem.
//
// Not part of the planetgen build: bench/richdem compiles it against a copy of RichDEM
// (github.com/r-barnes/richdem) kept outside the repository, so that bench_pits can
// print planetgen's times beside the field's reference implementation on the same
// file. It reads the DEM with OpenImageIO (one channel, raw heights), and for each
// algorithm named on the command line times only the algorithm on a fresh copy:
//   fill     PriorityFlood_Barnes2014   (Barnes, Lehman & Mulla 2014, improved)
//   breach   CompleteBreaching_Lindsay2016 (Lindsay 2016, complete breaching)
//   zhou     PriorityFlood_Zhou2016     (Zhou, Sun & Fu 2016)
//   wei      PriorityFlood_Wei2018      (Wei, Zhou & Dong 2018)
// Output: one line per algorithm, "richdem NAME SECONDS".
// usage: richdem_pits FILE.exr fill|breach|zhou|wei...
#include <OpenImageIO/imageio.h>
#include <richdem/common/Array2D.hpp>
#include <richdem/depressions/Barnes2014.hpp>
#include <richdem/depressions/Lindsay2016.hpp>
#include <richdem/depressions/Wei2018.hpp>
#include <richdem/depressions/Zhou2016.hpp>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <vector>

int main(int argc, char **argv) {
    if (argc < 3) {
        std::fprintf(stderr, "usage: richdem_pits FILE.exr fill|breach|zhou|wei...\n");
        return 2;
    }
    auto in = OIIO::ImageInput::open(argv[1]);
    if (!in) {
        std::fprintf(stderr, "%s: cannot read\n", argv[1]);
        return 2;
    }
    const OIIO::ImageSpec &spec = in->spec();
    const int w = spec.width, h = spec.height;
    std::vector<float> px((size_t)w * h);
    if (spec.nchannels != 1 || !in->read_image(0, 0, 0, 1, OIIO::TypeDesc::FLOAT, px.data())) {
        std::fprintf(stderr, "%s: expected a one-channel image\n", argv[1]);
        return 2;
    }
    in->close();
    for (int a = 2; a < argc; a++) {
        richdem::Array2D<float> dem(w, h);
        dem.setNoData(-1e30f);
        std::memcpy(dem.data(), px.data(), px.size() * sizeof(float));
        const std::string m = argv[a];
        auto t0 = std::chrono::steady_clock::now();
        if (m == "fill")
            richdem::PriorityFlood_Barnes2014<richdem::Topology::D8>(dem);
        else if (m == "breach")
            richdem::CompleteBreaching_Lindsay2016<richdem::Topology::D8>(dem);
        else if (m == "zhou")
            richdem::PriorityFlood_Zhou2016(dem);
        else if (m == "wei")
            richdem::PriorityFlood_Wei2018(dem);
        else {
            std::fprintf(stderr, "%s: unknown algorithm\n", argv[a]);
            return 2;
        }
        double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        std::printf("richdem %s %.3f\n", m.c_str(), s);
        std::fflush(stdout);
    }
    return 0;
}
