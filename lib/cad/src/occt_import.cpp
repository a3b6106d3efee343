// STEP and IGES through OpenCASCADE's XDE readers, which keep the assembly tree and part names
// (so --part can pick one body) and convert lengths to millimetres (xstep.cascade.unit = MM).
#include <BRep_Builder.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <IGESCAFControl_Reader.hxx>
#include <IGESData_GlobalSection.hxx>
#include <IGESData_IGESModel.hxx>
#include <Interface_Static.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Message_PrinterOStream.hxx>
#include <STEPCAFControl_Reader.hxx>
#include <STEPControl_Reader.hxx>
#include <Standard_Failure.hxx>
#include <TColStd_SequenceOfAsciiString.hxx>
#include <TCollection_AsciiString.hxx>
#include <TDF_LabelSequence.hxx>
#include <TDataStd_Name.hxx>
#include <TDocStd_Document.hxx>
#include <TopoDS_Compound.hxx>
#include <XCAFApp_Application.hxx>
#include <XCAFDoc_DocumentTool.hxx>
#include <XCAFDoc_ShapeTool.hxx>
#include <XSControl_WorkSession.hxx>

#include <functional>
#include <set>

#include "laserfit/cad/import.hpp"
#include "laserfit/cad/occt_mesh.hpp"
#include "laserfit/core/error.hpp"
#include "laserfit/io/util.hpp"

namespace laserfit::cad {
namespace {

std::string label_name(const TDF_Label& l) {
  Handle(TDataStd_Name) n;
  if (!l.FindAttribute(TDataStd_Name::GetID(), n)) return {};
  return TCollection_AsciiString(n->Get()).ToCString();
}

// Length unit name -> mm (STEP prefixes as OpenCASCADE reports them, IGES unit names).
double unit_name_to_mm(std::string u) {
  for (auto& c : u) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  if (u == "MM" || u == "MILLIMETRE" || u == "MILLIMETER") return 1.0;
  if (u == "M" || u == "METRE" || u == "METER") return 1000.0;
  if (u == "CM" || u == "CENTIMETRE") return 10.0;
  if (u == "IN" || u == "INCH" || u == "INCHES") return 25.4;
  if (u == "FT" || u == "FOOT") return 304.8;
  if (u == "UM" || u == "MICROMETRE" || u == "MICRON") return 1e-3;
  return 0.0;
}

// Silence OpenCASCADE's default console printer: its transfer statistics would otherwise end up
// in our --json stdout.
void quiet_occt() {
  static const bool done = [] {
    const Handle(Message_Messenger)& m = Message::DefaultMessenger();
    m->RemovePrinters(STANDARD_TYPE(Message_PrinterOStream));
    Interface_Static::SetCVal("xstep.cascade.unit", "MM");
    return true;
  }();
  (void)done;
}

}  // namespace

RawMesh read_with_occt(const std::string& path, const ImportSettings& s) {
  quiet_occt();
  RawMesh raw;
  const std::string ext = io::lower_extension(path);
  const bool step = ext == ".step" || ext == ".stp";

  Handle(TDocStd_Document) doc;
  XCAFApp_Application::GetApplication()->NewDocument("MDTV-XCAF", doc);
  try {
    if (step) {
      STEPCAFControl_Reader reader;
      reader.SetNameMode(true);
      if (reader.ReadFile(path.c_str()) != IFSelect_RetDone)
        throw Error(path, "cannot parse STEP file (corrupt, truncated or not STEP)");
      TColStd_SequenceOfAsciiString lengths, angles, solids;
      reader.ChangeReader().FileUnits(lengths, angles, solids);
      if (lengths.Length() > 0) {
        raw.declared_unit = lengths.First().ToCString();
        raw.declared_to_mm = unit_name_to_mm(raw.declared_unit);
      }
      if (!reader.Transfer(doc)) throw Error(path, "STEP file holds no transferable geometry");
    } else {
      IGESCAFControl_Reader reader;
      reader.SetNameMode(true);
      if (reader.ReadFile(path.c_str()) != IFSelect_RetDone)
        throw Error(path, "cannot parse IGES file (corrupt, truncated or not IGES)");
      const auto model = Handle(IGESData_IGESModel)::DownCast(reader.WS()->Model());
      if (!model.IsNull() && !model->GlobalSection().UnitName().IsNull()) {
        raw.declared_unit = model->GlobalSection().UnitName()->ToCString();
        raw.declared_to_mm = unit_name_to_mm(raw.declared_unit);
      }
      if (!reader.Transfer(doc)) throw Error(path, "IGES file holds no transferable geometry");
    }
  } catch (const Standard_Failure& e) {
    throw Error(path, std::string("OpenCASCADE failed to read it: ") + e.GetMessageString());
  }
  if (raw.declared_to_mm == 0.0) {
    raw.warnings.push_back("unit '" + raw.declared_unit + "' not recognised; assuming mm");
    raw.declared_unit = raw.declared_unit.empty() ? "none (assumed mm)" : raw.declared_unit;
    raw.declared_to_mm = 1.0;
  }

  // Walk the assembly tree; collect the selected bodies (all when no --part) with placement.
  const Handle(XCAFDoc_ShapeTool) tool = XCAFDoc_DocumentTool::ShapeTool(doc->Main());
  TDF_LabelSequence roots;
  tool->GetFreeShapes(roots);
  std::set<std::string> names;
  TopoDS_Compound selected;
  BRep_Builder builder;
  builder.MakeCompound(selected);
  bool matched = s.part.empty(), any = false;
  std::function<void(const TDF_Label&, const TopLoc_Location&, bool, const std::string&)> walk =
      [&](const TDF_Label& label, const TopLoc_Location& loc, bool take, const std::string& inst) {
        const std::string name = label_name(label);
        if (!name.empty()) names.insert(name);
        if (!s.part.empty() && (name == s.part || inst == s.part)) take = matched = true;
        if (XCAFDoc_ShapeTool::IsAssembly(label)) {
          TDF_LabelSequence comps;
          XCAFDoc_ShapeTool::GetComponents(label, comps);
          for (int i = 1; i <= comps.Length(); ++i) {
            TDF_Label ref;
            if (!XCAFDoc_ShapeTool::GetReferredShape(comps(i), ref)) continue;
            const std::string cname = label_name(comps(i));
            if (!cname.empty()) names.insert(cname);
            walk(ref, loc * XCAFDoc_ShapeTool::GetLocation(comps(i)), take, cname);
          }
        } else if (take) {
          builder.Add(selected, XCAFDoc_ShapeTool::GetShape(label).Moved(loc));
          any = true;
        }
      };
  for (int i = 1; i <= roots.Length(); ++i) walk(roots(i), TopLoc_Location(), s.part.empty(), "");
  raw.parts.assign(names.begin(), names.end());
  if (!matched) {
    std::string list;
    for (const auto& n : raw.parts) list += (list.empty() ? "" : ", ") + n;
    throw Error(path,
                "no part named '" + s.part + "' (parts: " + (list.empty() ? "none" : list) + ")");
  }
  if (!any) throw Error(path, "no solid or surface geometry in file");

  size_t skipped = 0;
  try {
    raw.mesh = tessellate(selected, {s.deflection_mm, s.angular_deflection_rad}, &skipped);
  } catch (const Standard_Failure& e) {
    throw Error(path, std::string("tessellation failed: ") + e.GetMessageString());
  }
  if (skipped > 0)
    raw.warnings.push_back(std::to_string(skipped) + " B-rep faces could not be tessellated");
  return raw;
}

}  // namespace laserfit::cad
