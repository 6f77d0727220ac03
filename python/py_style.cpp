// wisp.Style on the one style schema (groom/style_schema.hpp): fields are read as the TOML
// values style_field_toml writes and set through set_style_field, so Python checks every
// value with the reader's own rules and messages and repeats no field list.
#include <toml++/toml.h>

#include <cmath>
#include <sstream>

#include "bindings.hpp"
#include "core/error.hpp"
#include "groom/style_schema.hpp"
#include "groom/style_toml.hpp"

namespace wisp::python {
namespace {

py::object to_python(const toml::node& node) {
    if (const auto* v = node.as_integer()) return py::int_(v->get());
    if (const auto* v = node.as_floating_point()) return py::float_(v->get());
    if (const auto* v = node.as_boolean()) return py::bool_(v->get());
    if (const auto* v = node.as_string()) return py::str(v->get());
    if (const auto* a = node.as_array()) {
        py::list out;
        for (const toml::node& e : *a)
            out.append(to_python(e));
        return out;
    }
    if (const auto* t = node.as_table()) {
        py::dict out;
        for (const auto& [k, v] : *t)
            out[py::str(std::string(k.str()))] = to_python(v);
        return out;
    }
    return py::none();  // dates and times: no style field has them
}

// A Python value as an inline TOML value, for set_style_field to check. `where` names the
// field in messages.
void to_toml(const py::handle& v, const std::string& where, int depth, std::string& out) {
    if (depth > 16) throw py::value_error(where + ": value nested too deeply");
    const py::module_ builtins = py::module_::import("builtins");
    const bool is_array = py::isinstance<py::array>(v);
    const bool numpy_bool = !is_array && py::hasattr(v, "dtype") &&
                            py::str(v.attr("dtype").attr("kind")).cast<std::string>() == "b";
    if (py::isinstance<py::bool_>(v) || numpy_bool) {
        out += PyObject_IsTrue(v.ptr()) == 1 ? "true" : "false";
    } else if (py::isinstance<py::str>(v)) {
        out += toml_quote(v.cast<std::string>());
    } else if (py::hasattr(v, "__fspath__")) {
        out += toml_quote(py::module_::import("os").attr("fspath")(v).cast<std::string>());
    } else if (is_array || py::isinstance<py::list>(v) || py::isinstance<py::tuple>(v)) {
        const py::object seq =
            is_array ? v.attr("tolist")() : py::reinterpret_borrow<py::object>(v);
        if (!py::isinstance<py::list>(seq) && !py::isinstance<py::tuple>(seq)) {
            to_toml(seq, where, depth + 1, out);  // a 0-d array's item
            return;
        }
        out += "[";
        bool first = true;
        for (const py::handle& e : seq) {
            out += first ? "" : ", ";
            first = false;
            to_toml(e, where, depth + 1, out);
        }
        out += "]";
    } else if (py::isinstance<py::dict>(v)) {
        out += "{ ";
        bool first = true;
        for (const auto& [k, e] : v.cast<py::dict>()) {
            if (!py::isinstance<py::str>(k))
                throw py::type_error(where + ": table keys must be strings");
            out += first ? "" : ", ";
            first = false;
            out += toml_quote(k.cast<std::string>()) + " = ";
            to_toml(e, where, depth + 1, out);
        }
        out += " }";
    } else if (py::hasattr(v, "__index__")) {
        out += std::string(py::str(builtins.attr("int")(v)));
    } else if (py::hasattr(v, "__float__")) {
        // repr is the shortest text that reads back to the same double: "2.5", "1e+20",
        // "inf", "nan" are all TOML (the schema rejects the last two with its message).
        out += std::string(py::repr(builtins.attr("float")(v)));
    } else {
        throw py::type_error(where + ": cannot use a value of type " +
                             std::string(py::str(v.get_type().attr("__name__"))));
    }
}

}  // namespace

std::string inline_toml(const py::handle& v, const std::string& where) {
    std::string out;
    to_toml(v, where, 0, out);
    return out;
}

namespace {

py::object field_value(const PyStyle& s, const StyleField& field) {
    if (field.type == FieldType::kGroups)
        throw py::attribute_error(
            cat("field '", field.path, "': constraint groups are read and set as Style.groups"));
    const std::string text = style_field_toml(s.style, field, s.base_dir);
    if (text.empty()) return py::none();
    const toml::table t = toml::parse("value = " + text);
    return to_python(*t.get("value"));
}

const StyleField& field_at(std::string_view path) {
    const StyleField* f = find_style_field(path);
    if (!f) {
        // set_style_field's message, with its "did you mean".
        Style scratch;
        set_style_field(scratch, path, "0", "Style");
    }
    return *f;
}

py::object groups(const PyStyle& s) {
    const std::string text = groups_to_toml(s.style.groups, s.base_dir);
    py::list out;
    if (text.empty()) return out;
    const toml::table t = toml::parse(text);
    if (const toml::array* a = t["group"].as_array())
        for (const toml::node& g : *a)
            out.append(to_python(g));
    return out;
}

// Replaces the constraint groups: the style without its groups, then one [[group]] table per
// dict, read back by the style reader, so each group is checked as a file's would be.
void set_groups(PyStyle& s, const py::object& value) {
    if (!py::isinstance<py::list>(value) && !py::isinstance<py::tuple>(value))
        throw py::type_error("Style.groups: expected a list of dicts ([[group]] tables)");
    Style rest = s.style;
    rest.groups.clear();
    std::string text = style_to_toml(rest, s.base_dir);
    size_t i = 0;
    for (const py::handle& g : value) {
        const std::string where = cat("Style.groups[", i++, "]");
        if (!py::isinstance<py::dict>(g)) throw py::type_error(where + ": expected a dict");
        text += "\n[[group]]\n";
        for (const auto& [k, v] : g.cast<py::dict>()) {
            if (!py::isinstance<py::str>(k)) throw py::type_error(where + ": keys must be strings");
            text += toml_quote(k.cast<std::string>()) + " = " +
                    inline_toml(v, where + "." + k.cast<std::string>()) + "\n";
        }
    }
    Style next = parse_style(text, "Style.groups", s.base_dir);
    next.name = s.style.name;
    s.style = std::move(next);
}

}  // namespace

void bind_style(py::module_& m) {
    py::class_<PyStyle>(m, "_Style", "A style (docs/style.md); the wisp.Style class wraps it")
        .def(py::init<>())
        .def_static(
            "from_text",
            [](const std::string& text, const std::string& source, const std::string& base_dir) {
                return PyStyle{parse_style(text, source, base_dir), base_dir};
            },
            py::arg("text"), py::arg("source") = "style", py::arg("base_dir") = "")
        .def_static(
            "from_file",
            [](const std::string& path) {
                require_file(path, "style file");
                return PyStyle{load_style(path), std::filesystem::path(path).parent_path()};
            },
            py::arg("path"))
        .def_static("preset",
                    [](const std::string& name) {
                        return PyStyle{load_preset(name), {}};
                    })
        .def("to_toml", [](const PyStyle& s) { return style_to_toml(s.style, s.base_dir); })
        .def("copy", [](const PyStyle& s) { return s; })
        .def("get", [](const PyStyle& s,
                       const std::string& path) { return field_value(s, field_at(path)); })
        .def("set",
             [](PyStyle& s, const std::string& path, const py::object& value) {
                 const StyleField& field = field_at(path);
                 if (field.type == FieldType::kGroups)
                     throw py::attribute_error(
                         cat("field '", path, "': constraint groups are set as Style.groups"));
                 set_style_field(s.style, path, inline_toml(value, "field '" + path + "'"), "Style",
                                 s.base_dir);
             })
        .def_property("groups", &groups, &set_groups)
        .def_property_readonly("name", [](const PyStyle& s) { return s.style.name; })
        .def_property_readonly("base_dir", [](const PyStyle& s) { return s.base_dir.string(); });

    m.def("preset_names", &preset_names, "The shipped presets' names, sorted");
    m.def(
        "schema",
        [] {
            py::list out;
            for (const StyleField& f : style_schema()) {
                py::dict d;
                d["path"] = std::string(f.path);
                d["type"] = field_type_name(f.type);
                d["stage"] = stage_name(f.stage);
                d["unit"] = std::string(f.unit);
                d["paper"] = std::string(f.paper);
                d["doc"] = std::string(f.doc);
                if (f.lo != f.hi) d["range"] = py::make_tuple(f.lo, f.hi);
                py::list choices;
                for (std::string_view c : f.choices)
                    choices.append(std::string(c));
                d["choices"] = choices;
                out.append(d);
            }
            return out;
        },
        "Every style field: path, type, stage, unit, paper, doc, range, choices");
    m.def(
        "sections",
        [] {
            py::dict out;
            for (const std::string& s : style_sections())
                out[py::str(s)] = section_keys(s);
            return out;
        },
        "Each style section's keys (fields and sub-sections), '' being the top level");
}

}  // namespace wisp::python
