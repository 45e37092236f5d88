// A flat C interface over TetGen's tetrahedralize(): arrays in, arrays out, and every way
// TetGen can fail (thrown int codes, failed assertions, bad_alloc, anything else) turned into
// a return code. TetGen's own printout (it prints the details of a failure to stdout even in
// quiet mode) is captured and handed back as text, so callers' stdout stays clean.
#include <new>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#if defined(__unix__) || defined(__APPLE__)
#include <unistd.h>
#define SHIM_CAPTURE 1
#endif
#include "tetgen.h"

extern char tetgen_shim_assert_text[512];

extern "C" {

/// Output of one call. Arrays are malloc'ed; release them with tetgen_shim_free.
struct TetgenShimOutput {
  int code;          // 0 success; TetGen's thrown code (1..10); -1 unknown exception
  int status;        // tetrahedralize's return value (non-zero: setup failed)
  int num_points;
  double *points;    // 3 * num_points
  int num_tets;
  int *tets;         // 4 * num_tets, 0-based
  int num_faces;
  int *faces;        // 3 * num_faces, 0-based boundary faces
  char *message;     // what TetGen printed (and the failed assertion), NUL-terminated
};

void tetgen_shim_free(TetgenShimOutput *out);

}  // extern "C"

namespace {

// Redirects file descriptor 1 into a temporary file while alive.
struct StdoutCapture {
#ifdef SHIM_CAPTURE
  FILE *tmp = nullptr;
  int saved = -1;
  StdoutCapture() {
    fflush(stdout);
    tmp = tmpfile();
    if (!tmp) return;
    saved = dup(1);
    if (saved < 0 || dup2(fileno(tmp), 1) < 0) {
      if (saved >= 0) close(saved);
      saved = -1;
      fclose(tmp);
      tmp = nullptr;
    }
  }
  // Restores stdout and returns what was written (malloc'ed, NUL-terminated).
  char *finish() {
    if (!tmp) return nullptr;
    fflush(stdout);
    dup2(saved, 1);
    close(saved);
    saved = -1;
    long size = ftell(tmp);
    if (size < 0) size = 0;
    const long keep = 4096;  // the first lines say what went wrong
    if (size > keep) size = keep;
    char *text = (char *)malloc((size_t)size + 1);
    if (text) {
      rewind(tmp);
      size_t got = fread(text, 1, (size_t)size, tmp);
      text[got] = '\0';
    }
    fclose(tmp);
    tmp = nullptr;
    return text;
  }
  ~StdoutCapture() { free(finish()); }
#else
  char *finish() { return nullptr; }
#endif
};

template <typename T>
T *copy_array(const T *src, size_t n) {
  if (!src || n == 0) return nullptr;
  T *dst = (T *)malloc(n * sizeof(T));
  if (!dst) throw std::bad_alloc();
  memcpy(dst, src, n * sizeof(T));
  return dst;
}

char *append_text(char *text, const char *extra) {
  size_t a = text ? strlen(text) : 0, b = strlen(extra);
  char *joined = (char *)realloc(text, a + b + 2);
  if (!joined) return text;
  if (a > 0 && joined[a - 1] != '\n') joined[a++] = '\n';
  memcpy(joined + a, extra, b + 1);
  return joined;
}

}  // namespace

extern "C" {

void tetgen_shim_free(TetgenShimOutput *out) {
  if (!out) return;
  free(out->points);
  free(out->tets);
  free(out->faces);
  free(out->message);
  memset(out, 0, sizeof *out);
}

/// Tetrahedralizes the closed triangle surface (points: 3 * num_points coordinates,
/// triangles: 3 * num_triangles 0-based indices) with TetGen's command-line switches.
/// Returns out->code (0 on success).
int tetgen_shim_tetrahedralize(const char *switches, const double *points, int num_points,
                               const int *triangles, int num_triangles,
                               TetgenShimOutput *out) {
  memset(out, 0, sizeof *out);
  tetgen_shim_assert_text[0] = '\0';
  StdoutCapture capture;
  try {
    tetgenio in, result;
    in.firstnumber = 0;
    in.mesh_dim = 3;
    in.numberofpoints = num_points;
    in.pointlist = new double[(size_t)num_points * 3];
    memcpy(in.pointlist, points, (size_t)num_points * 3 * sizeof(double));
    in.numberoffacets = num_triangles;
    in.facetlist = new tetgenio::facet[num_triangles];
    for (int i = 0; i < num_triangles; ++i) {
      tetgenio::facet *f = &in.facetlist[i];
      tetgenio::init(f);
      f->numberofpolygons = 1;
      f->polygonlist = new tetgenio::polygon[1];
      tetgenio::polygon *p = &f->polygonlist[0];
      tetgenio::init(p);
      p->numberofvertices = 3;
      p->vertexlist = new int[3];
      for (int k = 0; k < 3; ++k) p->vertexlist[k] = triangles[3 * i + k];
    }
    out->status = tetrahedralize(switches, &in, &result);
    out->num_points = result.numberofpoints;
    out->points = copy_array(result.pointlist, (size_t)result.numberofpoints * 3);
    if (result.numberofcorners == 4) {
      out->num_tets = result.numberoftetrahedra;
      out->tets = copy_array(result.tetrahedronlist, (size_t)result.numberoftetrahedra * 4);
    }
    out->num_faces = result.numberoftrifaces;
    out->faces = copy_array(result.trifacelist, (size_t)result.numberoftrifaces * 3);
  } catch (int code) {
    out->code = code == 0 ? -1 : code;
  } catch (const std::bad_alloc &) {
    out->code = 1;
  } catch (...) {
    out->code = -1;
  }
  out->message = capture.finish();
  if (tetgen_shim_assert_text[0] != '\0') {
    out->message = append_text(out->message, tetgen_shim_assert_text);
  }
  if (out->code != 0) {
    free(out->points);
    free(out->tets);
    free(out->faces);
    out->points = nullptr;
    out->tets = nullptr;
    out->faces = nullptr;
    out->num_points = out->num_tets = out->num_faces = 0;
  }
  return out->code;
}

}  // extern "C"
