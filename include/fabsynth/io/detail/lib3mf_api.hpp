// SPDX-License-Identifier: MIT
#pragma once
/// @file lib3mf_api.hpp  The part of lib3mf 1.x's plain C interface (Model/COM/NMR_DLLInterfaces.h)
/// that io/mesh_3mf.hpp calls, declared here instead of including lib3mf's headers: those
/// define Windows-style typedefs at global scope (BOOL, DWORD, HRESULT, INT, ...) and macros
/// (_In_, _Out_, ...) that a header-only library must not push into its users' code.
///
/// Each function is declared as a C++ function in this namespace, bound to lib3mf's C symbol with
/// an asm label (GCC and Clang). Not extern "C": such names are one entity across all
/// namespaces, so they could clash with lib3mf's own declarations or anyone's `release`. A
/// translation unit may include lib3mf's headers as well. The types are lib3mf's on every platform it builds the emulated COM interface for
/// (LIB3MFRESULT = int, BOOL = int, DWORD = unsigned int, ULONG64 = unsigned long long; handles
/// are pointers; MODELMESHVERTEX is float[3], MODELMESHTRIANGLE DWORD[3] and MODELTRANSFORM
/// float[3][4], all packed); mesh_3mf.hpp checks the interface version at run time (major 1).
/// cmake/Findlib3mf.cmake accepts only a lib3mf that ships this 1.x interface header.
#if !defined(__GNUC__) && !defined(__clang__)
#error "fabsynth/io/mesh_3mf.hpp binds lib3mf's C symbols with asm labels and needs GCC or Clang"
#endif

namespace fabsynth::io::detail::lib3mf {

using result = int;        // LIB3MFRESULT: 0 = success
using handle = void*;      // every lib3mf object (model, reader, writer, resource, iterator)
using dword = unsigned int;
using boolean = int;
using ulong64 = unsigned long long;

struct vertex {
    float position[3];
};
struct triangle {
    dword indices[3];
};
struct transform {
    float fields[3][4];  // rows of [R | t]
};
struct colour {  // MODELMESHCOLOR_SRGB
    unsigned char red, green, blue, alpha;
};
struct triangle_colour {  // MODELMESH_TRIANGLECOLOR_SRGB: one colour per corner
    colour corners[3];
};
static_assert(sizeof(vertex) == 12 && sizeof(triangle) == 12 && sizeof(transform) == 48);
static_assert(sizeof(colour) == 4 && sizeof(triangle_colour) == 12);

/// lib3mf's property type of a triangle (eModelPropertyType, an int-sized enum).
inline constexpr dword property_none = 0, property_colour = 2;

/// lib3mf's unit ids (eModelUnit).
inline constexpr dword unit_micrometer = 0, unit_millimeter = 1, unit_centimeter = 2, unit_inch = 3, unit_foot = 4,
                       unit_meter = 5;

// C++ declarations (not extern "C", whose names would be global across namespaces) bound to lib3mf's C symbols.
result getinterfaceversion(dword* major, dword* minor, dword* micro) __asm__("lib3mf_getinterfaceversion");
result createmodel(handle* model) __asm__("lib3mf_createmodel");
result release(handle instance) __asm__("lib3mf_release");
result getlasterror(handle instance, dword* code, const char** message) __asm__("lib3mf_getlasterror");

result model_setunit(handle model, dword unit) __asm__("lib3mf_model_setunit");
result model_getunit(handle model, dword* unit) __asm__("lib3mf_model_getunit");
result model_addmeshobject(handle model, handle* mesh) __asm__("lib3mf_model_addmeshobject");
result model_addbuilditem(handle model, handle object, transform* t, handle* item) __asm__("lib3mf_model_addbuilditem");
result model_getbuilditems(handle model, handle* iterator) __asm__("lib3mf_model_getbuilditems");
result model_querywriter(handle model, const char* writer_class, handle* writer) __asm__("lib3mf_model_querywriter");
result model_queryreader(handle model, const char* reader_class, handle* reader) __asm__("lib3mf_model_queryreader");

result writer_getstreamsize(handle writer, ulong64* size) __asm__("lib3mf_writer_getstreamsize");
result writer_writetobuffer(handle writer, unsigned char* buffer, ulong64 size) __asm__("lib3mf_writer_writetobuffer");
result reader_readfrombuffer(handle reader, unsigned char* buffer, ulong64 size) __asm__("lib3mf_reader_readfrombuffer");

result object_setnameutf8(handle object, const char* name) __asm__("lib3mf_object_setnameutf8");
result object_ismeshobject(handle object, boolean* is_mesh) __asm__("lib3mf_object_ismeshobject");
result object_setuuidutf8(handle object, const char* uuid) __asm__("lib3mf_object_setuuidutf8");
result model_setbuilduuidutf8(handle model, const char* uuid) __asm__("lib3mf_model_setbuilduuidutf8");
result builditem_setuuidutf8(handle item, const char* uuid) __asm__("lib3mf_builditem_setuuidutf8");

result builditemiterator_movenext(handle iterator, boolean* has_next) __asm__("lib3mf_builditemiterator_movenext");
result builditemiterator_getcurrent(handle iterator, handle* item) __asm__("lib3mf_builditemiterator_getcurrent");
result builditem_getobjectresource(handle item, handle* object) __asm__("lib3mf_builditem_getobjectresource");
result builditem_getobjecttransform(handle item, transform* t) __asm__("lib3mf_builditem_getobjecttransform");

result meshobject_getvertexcount(handle mesh, dword* count) __asm__("lib3mf_meshobject_getvertexcount");
result meshobject_gettrianglecount(handle mesh, dword* count) __asm__("lib3mf_meshobject_gettrianglecount");
result meshobject_getvertices(handle mesh, vertex* out, dword buffer_size, dword* count) __asm__("lib3mf_meshobject_getvertices");
result meshobject_gettriangleindices(handle mesh, triangle* out, dword buffer_size, dword* count)
    __asm__("lib3mf_meshobject_gettriangleindices");
result meshobject_setgeometry(handle mesh, vertex* vertices, dword vertex_count, triangle* triangles, dword triangle_count)
    __asm__("lib3mf_meshobject_setgeometry");

// per-triangle properties (colours) of a mesh object
result meshobject_createpropertyhandler(handle mesh, handle* handler) __asm__("lib3mf_meshobject_createpropertyhandler");
result propertyhandler_setsinglecolorrgb(handle handler, dword triangle, unsigned char red, unsigned char green, unsigned char blue)
    __asm__("lib3mf_propertyhandler_setsinglecolorrgb");
result propertyhandler_getpropertytype(handle handler, dword triangle, dword* type) __asm__("lib3mf_propertyhandler_getpropertytype");
result propertyhandler_getcolor(handle handler, dword triangle, triangle_colour* colour) __asm__("lib3mf_propertyhandler_getcolor");
// the object's default property (lib3mf requires one when triangles have properties)
result object_createdefaultpropertyhandler(handle object, handle* handler) __asm__("lib3mf_object_createdefaultpropertyhandler");
result defaultpropertyhandler_setcolorrgb(handle handler, unsigned char red, unsigned char green, unsigned char blue)
    __asm__("lib3mf_defaultpropertyhandler_setcolorrgb");

}  // namespace fabsynth::io::detail::lib3mf
