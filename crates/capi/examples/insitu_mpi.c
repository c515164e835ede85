/* In situ from C: an MPI application whose processes each hold their own share of the glyphs
 * hands them, with its communicator, to the C ABI, and the root gets the frame of all of them
 * -- no file written or read on the way.
 *
 *   scripts/install-capi.sh PREFIX   (the library built with: cargo build --release
 *                                     -p ellipsoid-splat-capi --features mpi)
 *   mpicc -std=c11 insitu_mpi.c $(PKG_CONFIG_PATH=PREFIX/lib/pkgconfig pkg-config --cflags
 *         --libs ellipsoid_splat) -Wl,-rpath,PREFIX/lib -o insitu_mpi
 *   mpirun -n 4 ./insitu_mpi
 *
 * Each rank makes its share of one scene (a hash of the glyph index decides each glyph and
 * its rank), renders it composited over MPI_COMM_WORLD at rank 0, then over a communicator
 * of its own (the ranks split in reverse order, so the root is the world's last rank; freed
 * by this program afterwards, as the library never frees a host's communicator). The root
 * also draws the whole scene alone through the same ABI and compares the two frames bit for
 * bit (colour, depth, normal, id), printing `case NAME: match, N pixels shown`; any mismatch
 * exits with status 1. Validation is on: any message fails the call that caused it.
 *
 * With `--fail-rank R`, rank R's share holds a glyph with a zero semi-axis: every rank must
 * get an error (R its own, the others ES_STATUS_ERROR_OTHER_RANK naming R), and the root
 * prints each rank's `rank K stopped: MESSAGE`; a rank left waiting would keep mpirun from
 * ending.
 *
 * Run by crates/capi/tests/insitu_mpi.rs. */
#define ELLIPSOID_SPLAT_MPI 1 /* declares es_offscreen_render_composited */
#include <ellipsoid_splat.h>
#include <mpi.h>

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { GLYPHS = 2000, WIDTH = 160, HEIGHT = 120 };

/* SplitMix64: a fixed, well-spread hash of an index (the same on every rank). */
static uint64_t mix(uint64_t z) {
    z += 0x9E3779B97F4A7C15ull;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

/* A number in [0, 1) from the hash of `seed`. */
static double unit(uint64_t seed) { return (double)(mix(seed) >> 11) / 9007199254740992.0; }

/* Glyph `i` of the whole scene: in a cube of side 12, sized and turned by the hash. */
static EsGlyph glyph(uint64_t i) {
    EsGlyph g;
    for (int k = 0; k < 3; k++) {
        g.center[k] = unit(i * 16 + k) * 12.0 - 6.0;
        g.radii[k] = unit(i * 16 + 3 + k) * 0.45 + 0.15;
        g.color[k] = (float)unit(i * 16 + 10 + k);
    }
    for (int k = 0; k < 4; k++) g.rotation[k] = unit(i * 16 + 6 + k) - 0.5;
    g.rotation[0] += 1e-3; /* never zero */
    return g;
}

/* The rank of a communicator of `size` that holds glyph `i`. */
static int owner(uint64_t i, int size) { return (int)(mix(i ^ 0x5EEDull) % (uint64_t)size); }

/* A frame's arrays. */
typedef struct Image {
    uint8_t color[WIDTH * HEIGHT * 4];
    float depth[WIDTH * HEIGHT];
    float normal[WIDTH * HEIGHT * 3];
    uint32_t id[WIDTH * HEIGHT];
} Image;

static EsFrameBuffers buffers_of(Image *image) {
    EsFrameBuffers b = {sizeof(EsFrameBuffers), image->color, image->depth, image->normal,
                        image->id};
    return b;
}

/* Reports a failed call on this rank; returns 1. One write, so ranks' lines do not mix. */
static int failed(int rank, const char *what) {
    fprintf(stderr, "insitu_mpi: rank %d: %s: %s\n", rank, what, es_last_error());
    return 1;
}

/* Draws this rank's share over `comm` (composited at `root`) and, at the root, the whole scene
 * alone; compares them. Returns 0 on a match, 1 on a failure or mismatch. */
static int run_case(const char *name, MPI_Comm comm, int root, EsOffscreenRenderer *renderer,
                    const EsCamera *camera, const EsGlyph *all, Image *composited,
                    Image *alone) {
    int rank, size, world_rank;
    MPI_Comm_rank(comm, &rank);
    MPI_Comm_size(comm, &size);
    MPI_Comm_rank(MPI_COMM_WORLD, &world_rank);
    static EsGlyph mine[GLYPHS];
    static uint32_t ids[GLYPHS];
    size_t count = 0;
    for (uint32_t i = 0; i < GLYPHS; i++) {
        if (owner(i, size) == rank) {
            mine[count] = all[i];
            ids[count++] = i; /* increasing, as the call requires */
        }
    }
    EsFrameBuffers out = buffers_of(composited);
    EsStatus status = es_offscreen_render_composited(renderer, MPI_Comm_c2f(comm), root, mine,
                                                     ids, count, camera,
                                                     rank == root ? &out : NULL);
    if (status != ES_STATUS_SUCCESS) return failed(world_rank, name);
    if (rank != root) return 0;
    EsFrameBuffers whole = buffers_of(alone);
    if (es_offscreen_render(renderer, all, GLYPHS, camera, &whole) != ES_STATUS_SUCCESS) {
        return failed(world_rank, "the whole scene alone");
    }
    int same = memcmp(composited, alone, sizeof(Image)) == 0; /* every output, bit for bit */
    size_t shown = 0;
    for (size_t p = 0; p < WIDTH * HEIGHT; p++) shown += alone->id[p] != ES_NO_GLYPH;
    printf("case %s: %s, %zu pixels shown\n", name, same ? "match" : "MISMATCH", shown);
    fflush(stdout);
    return same && shown > 0 ? 0 : 1;
}

/* `--fail-rank R`: every rank's call must fail, R's with its own error. */
static int run_failure(int failing, EsOffscreenRenderer *renderer, const EsCamera *camera,
                       const EsGlyph *all) {
    int rank, size;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    EsGlyph mine[100];
    uint32_t ids[100];
    for (uint32_t i = 0; i < 100; i++) {
        mine[i] = all[i];
        ids[i] = i;
    }
    if (rank == failing) mine[7].radii[1] = 0.0;
    static Image image;
    EsFrameBuffers out = buffers_of(&image);
    EsStatus status = es_offscreen_render_composited(renderer, MPI_Comm_c2f(MPI_COMM_WORLD), 0,
                                                     mine, ids, 100, camera, &out);
    EsStatus expected =
        rank == failing ? ES_STATUS_ERROR_INVALID_ARGUMENT : ES_STATUS_ERROR_OTHER_RANK;
    if (status != expected) {
        fprintf(stderr, "insitu_mpi: rank %d: status %d, %d expected: %s\n", rank, (int)status,
                (int)expected, es_last_error());
        return 1;
    }
    /* MPI still works after the failure: the root prints every rank's line, whole. */
    enum { LINE = 512 };
    char line[LINE];
    snprintf(line, LINE, "rank %d stopped: %s", rank, es_last_error());
    char *lines = rank == 0 ? malloc((size_t)size * LINE) : NULL;
    MPI_Gather(line, LINE, MPI_CHAR, lines, LINE, MPI_CHAR, 0, MPI_COMM_WORLD);
    if (lines) {
        for (int k = 0; k < size; k++) printf("%s\n", lines + (size_t)k * LINE);
        fflush(stdout);
        free(lines);
    }
    return 0;
}

int main(int argc, char **argv) {
    MPI_Init(&argc, &argv);
    int rank, size;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    int failing = -1;
    if (argc == 3 && strcmp(argv[1], "--fail-rank") == 0) failing = atoi(argv[2]);

    EsOffscreenCreateInfo info = {sizeof(EsOffscreenCreateInfo), 1, NULL, NULL};
    EsOffscreenRenderer *renderer = NULL;
    int bad = 0;
    if (es_offscreen_create(&info, &renderer) != ES_STATUS_SUCCESS) {
        bad = failed(rank, "es_offscreen_create");
    }
    static EsGlyph all[GLYPHS];
    for (uint32_t i = 0; i < GLYPHS; i++) all[i] = glyph(i);
    const double eye[3] = {4.0, 6.0, 30.0}, target[3] = {0.0, 0.0, 0.0}, up[3] = {0.0, 1.0, 0.0};
    EsCamera camera;
    if (!bad && es_camera_look_at(eye, target, up, 45.0, 5.0, WIDTH, HEIGHT, &camera) !=
                    ES_STATUS_SUCCESS) {
        bad = failed(rank, "es_camera_look_at");
    }
    /* Every rank starts only where every rank could make its renderer. */
    int any_bad = 0;
    MPI_Allreduce(&bad, &any_bad, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
    if (!any_bad) {
        static Image composited, alone;
        if (failing >= 0) {
            bad = run_failure(failing, renderer, &camera, all);
        } else {
            bad = run_case("world", MPI_COMM_WORLD, 0, renderer, &camera, all, &composited,
                           &alone);
            /* A communicator the application made: the ranks in reverse order. */
            MPI_Comm reversed;
            MPI_Comm_split(MPI_COMM_WORLD, 0, size - 1 - rank, &reversed);
            bad |= run_case("reversed", reversed, 0, renderer, &camera, all, &composited,
                            &alone);
            MPI_Comm_free(&reversed); /* still the application's: the library did not free it */
        }
    }
    if (renderer && es_offscreen_destroy(renderer) != ES_STATUS_SUCCESS) {
        bad = failed(rank, "es_offscreen_destroy");
    }
    MPI_Finalize();
    return bad || any_bad;
}
