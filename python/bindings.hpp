#pragma once
// The pieces of the `wisp._wisp` extension (docs/python.md), one file each: the style and
// its schema (py_style.cpp), heads and hair with their numpy views, reading and writing
// (py_hair.cpp), the renderer (py_render.cpp), the pipeline stages, generate and animate
// (py_stages.cpp). The Python package (wisp/__init__.py) builds the user-facing API on them.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>  // paths as str or os.PathLike
#include <tbb/task_arena.h>

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "groom/head.hpp"
#include "groom/style.hpp"

namespace wisp::python {

namespace py = pybind11;

void bind_style(py::module_& m);
void bind_hair(py::module_& m);
void bind_render(py::module_& m);
void bind_stages(py::module_& m);

// A style and the folder its relative paths (maps, OBJ heads) resolve against.
struct PyStyle {
    Style style;
    std::filesystem::path base_dir;
};

// A head shared by the Python objects that use it (a Hair made on it keeps it alive).
using HeadPtr = std::shared_ptr<Head>;

// A Python value (bool, int, float, str, path, list, tuple, dict, numpy array or scalar) as
// an inline TOML value for set_style_field; raises TypeError naming `where` for others.
std::string inline_toml(const py::handle& value, const std::string& where);

// Arrays from Python, checked at the boundary: numpy.asarray of `o`, or TypeError naming
// `name` for None and non-numeric dtypes.
py::array as_array(const py::object& o, const std::string& name);
std::string shape_text(const py::array& a);  // "(2, 3)"
std::string dtype_text(const py::array& a);  // "float64"
// A float32 copy (C order) of a floating-point array of shape (rows, cols) (rows −1: any;
// cols 0: 1-D), every value finite; TypeError or ValueError naming `name`, the expected
// `shape` and what was found.
py::array_t<float, py::array::c_style> float_array(const py::object& o, const std::string& name,
                                                   py::ssize_t rows, py::ssize_t cols,
                                                   const char* shape);
// A 1-D integer array of `rows` values (−1: any) as int64, checked as float_array.
std::vector<int64_t> int_array(const py::object& o, const std::string& name, py::ssize_t rows,
                               const char* shape);
// CSR offsets (rows values, −1: any) as int64: int_array, then 0 first, non-decreasing and
// `last` (described as `last_is`, "the point count") last.
std::vector<int64_t> offsets_array(const py::object& o, const std::string& name, py::ssize_t rows,
                                   const char* shape, int64_t last, const char* last_is);

// Raises FileNotFoundError naming `what` and the path unless the file exists.
void require_file(const std::filesystem::path& path, const char* what);

// The worker threads of a call: None (all cores) or an integer ≥ 1; raises ValueError
// otherwise. 0 is taken as "all cores", as the CLI's --threads 0.
int thread_count(const py::object& threads);

// Runs f without the GIL in a task arena of `threads` workers (0: all cores), so that the
// count holds for this call only (tbb::global_control would limit every thread of the
// process, including another Python thread's generate).
template <typename F>
auto run_released(int threads, F&& f) {
    py::gil_scoped_release release;
    if (threads <= 0) return f();
    tbb::task_arena arena(threads);
    return arena.execute(std::forward<F>(f));
}

// A numpy array viewing `data` (no copy) whose base is `owner`, so the memory lives as long
// as the array does. `writeable` false marks it read-only (arrays whose change would break
// an invariant, such as offsets).
template <typename T>
py::array view(const py::handle& owner, const T* data, std::vector<py::ssize_t> shape,
               bool writeable = true) {
    // numpy allocates (and would not take the base) for a null pointer: an empty vector's.
    alignas(16) static const unsigned char empty[16] = {};
    const void* ptr = data ? static_cast<const void*>(data) : empty;
    py::array a(py::dtype::of<T>(), std::move(shape), {}, ptr, owner);
    if (!writeable)
        py::detail::array_proxy(a.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
    return a;
}

}  // namespace wisp::python
