// Stand-in for LAMMPS' bundled fmt 7 (`fmt::v7_lmp`), which liblammps-dev's headers include
// ("fmt/format.h") but Debian does not ship; Debian's fmt 9 lacks `fmt::make_args_checked`,
// which those headers call, and its types are not the ones liblammps was compiled with.
//
// This header declares only what the LAMMPS headers name, so that they parse: the formatted
// overloads of Error::all/one/warning/message and utils::logmesg (templates that would call
// `fmt::make_args_checked`) cannot be instantiated, because `make_args_checked` is deleted.
// Code built with it must call the plain `const std::string &` overloads (Error::all(FLERR,
// std::string(...))), so no fmt object ever crosses into liblammps. A call that would pick a
// formatted overload (a string literal as the message, or format arguments) fails to compile.
#ifndef ROLLSLIDE_LAMMPS_FMT_COMPAT_H
#define ROLLSLIDE_LAMMPS_FMT_COMPAT_H

namespace fmt {
// Named by the private declarations of Error::_all & co. and utils::fmtargs_logmesg, which
// this code never calls (their definitions in liblammps take fmt 7's types).
class string_view {
  public:
    template <typename S> string_view(const S &) = delete;
};
class format_args {};
// Deleted: instantiating any formatted LAMMPS helper is a compile-time error.
template <typename... Args, typename S, typename... T>
format_args make_args_checked(const S &, const T &...) = delete;
}    // namespace fmt

#endif
