// The `wisp._wisp` extension module: wisp::Error becomes `wisp.Error`, a ValueError, so that
// bad input from Python is an exception with the library's message, never a crash.
#include <thread>

#include "bindings.hpp"
#include "core/error.hpp"

namespace wisp::python {

void require_file(const std::filesystem::path& path, const char* what) {
    std::error_code ec;
    if (std::filesystem::is_regular_file(path, ec)) return;
    const std::string message =
        cat(what, " '", path.string(),
            "': ", std::filesystem::exists(path, ec) ? "not a regular file" : "no such file");
    PyErr_SetString(PyExc_FileNotFoundError, message.c_str());
    throw py::error_already_set();
}

int thread_count(const py::object& threads) {
    if (threads.is_none()) return 0;
    if (py::isinstance<py::bool_>(threads) || !py::isinstance<py::int_>(threads))
        throw py::type_error(cat("threads: expected None or an integer, got ",
                                 std::string(py::str(threads.get_type().attr("__name__")))));
    const long long n = threads.cast<long long>();
    if (n < 0 || n > 4096)
        throw py::value_error(cat("threads: expected None, 0 (all cores) or 1 to 4096, got ", n));
    return static_cast<int>(n);
}

}  // namespace wisp::python

PYBIND11_MODULE(_wisp, m) {
    using namespace wisp::python;
    m.doc() = "wisp's C++ library (the `wisp` package wraps it; docs/python.md)";
    m.attr("__version__") = WISP_VERSION;
    py::register_exception<wisp::Error>(m, "Error", PyExc_ValueError);
    bind_style(m);
    bind_hair(m);
    bind_render(m);
    bind_stages(m);
}
