// CAD import on real files (tests/data/o2ac, Team O2AC, MIT) in every supported format.
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <gtest/gtest.h>
#include <BRepPrimAPI_MakeBox.hxx>
#include <IGESControl_Controller.hxx>
#include <IGESControl_Writer.hxx>
#include <STEPCAFControl_Writer.hxx>
#include <STEPControl_Reader.hxx>
#include <TDataStd_Name.hxx>
#include <TDocStd_Document.hxx>
#include <XCAFApp_Application.hxx>
#include <XCAFDoc_DocumentTool.hxx>
#include <XCAFDoc_ShapeTool.hxx>

#include <assimp/Exporter.hpp>
#include <assimp/Importer.hpp>
#include <filesystem>

#include "laserfit/cad/import.hpp"
#include "laserfit/core/error.hpp"
#include "laserfit/io/mesh_writer.hpp"
#include "test_util.hpp"

using namespace laserfit;
using laserfit::test::data;

namespace {

const Eigen::Vector3f kPanel(70, 60, 20);  // README of the o2ac files

cad::ImportResult import(const std::string& path, cad::ImportSettings s = {}) {
  return cad::import_cad(path, s);
}

// Re-export a file through assimp's own exporter (format id), optionally scaling the root node.
void reexport(const std::string& in, const std::string& out, const char* format, float scale = 1) {
  Assimp::Importer imp;
  const aiScene* scene = imp.ReadFile(in, aiProcess_Triangulate);
  ASSERT_NE(scene, nullptr) << imp.GetErrorString();
  aiScene* s = imp.GetOrphanedScene();
  s->mRootNode->mTransformation =
      aiMatrix4x4(scale, 0, 0, 0, 0, scale, 0, 0, 0, 0, scale, 0, 0, 0, 0, 1) *
      s->mRootNode->mTransformation;
  Assimp::Exporter exp;
  ASSERT_EQ(exp.Export(s, format, out), AI_SUCCESS) << format << ": " << exp.GetErrorString();
  delete s;
}

}  // namespace

TEST(Import, PanelStepAndStlAgreeOnBoundingBox) {
  // Tolerance: 0.02 mm = twice the default chordal deflection (0.01 mm) of the STEP tessellation.
  const auto step = import(data("o2ac/02-PANEL.step"));
  const auto stl = import(data("o2ac/02-PANEL.stl"));
  EXPECT_EQ(step.reader, "opencascade");
  EXPECT_EQ(step.unit_source, "file");
  EXPECT_EQ(stl.unit_source, "guess");
  EXPECT_EQ(stl.mesh.faces.size(), 1150u);
  EXPECT_LT((step.mesh.extent() - kPanel).cwiseAbs().maxCoeff(), 0.02);
  EXPECT_LT((stl.mesh.extent() - kPanel).cwiseAbs().maxCoeff(), 1e-3);
  EXPECT_LT((step.mesh.bbox().min() - stl.mesh.bbox().min()).cwiseAbs().maxCoeff(), 0.02);
  EXPECT_TRUE(step.repair.watertight);
  EXPECT_TRUE(stl.repair.watertight);
  // Same solid, same volume: within 0.5 % (tessellation of the curved holes).
  EXPECT_NEAR(step.repair.volume_mm3, stl.repair.volume_mm3, 0.005 * stl.repair.volume_mm3);
}

TEST(Import, StepDeflectionControlsTessellation) {
  cad::ImportSettings coarse, fine;
  coarse.deflection_mm = 0.1;
  fine.deflection_mm = 0.002;
  const auto c = import(data("o2ac/02-PANEL.step"), coarse),
             f = import(data("o2ac/02-PANEL.step"), fine);
  EXPECT_GT(f.mesh.faces.size(), c.mesh.faces.size());
  EXPECT_LT((f.mesh.extent() - kPanel).cwiseAbs().maxCoeff(), 0.004);  // 2x deflection
}

TEST(Import, GearMotorObjAndDaeAgree) {
  // Tolerance 1e-3 mm: both files hold the same vertices.
  const auto obj = import(data("o2ac/04_37D-GEARMOTOR-50-70.obj"));
  const auto dae = import(data("o2ac/04_37D-GEARMOTOR-50-70.dae"));
  EXPECT_EQ(obj.mesh.faces.size(), 9872u);
  EXPECT_EQ(dae.mesh.faces.size(), obj.mesh.faces.size());
  EXPECT_LT((obj.mesh.extent() - Eigen::Vector3f(36.8f, 36.8f, 81.7f)).cwiseAbs().maxCoeff(), 0.05);
  EXPECT_LT((obj.mesh.bbox().min() - dae.mesh.bbox().min()).cwiseAbs().maxCoeff(), 1e-3);
  EXPECT_LT((obj.mesh.bbox().max() - dae.mesh.bbox().max()).cwiseAbs().maxCoeff(), 1e-3);
}

TEST(Import, AsciiStl) {
  const auto r = import(data("o2ac/endcap_EDCS10.stl"));
  EXPECT_EQ(r.mesh.faces.size(), 576u);
  EXPECT_LT((r.mesh.extent() - Eigen::Vector3f(5, 14, 14)).cwiseAbs().maxCoeff(), 0.01);
}

TEST(Import, EveryAssimpFormatRoundTrips) {
  // The panel re-exported by assimp to each format must import to the same box (1e-3 mm).
  test::TempDir dir;
  const std::string src = data("o2ac/02-PANEL.stl").string();
  struct Case {
    const char* file;
    const char* format;
    float scale;
  };
  for (const Case& c : {Case{"p.ply", "plyb", 1}, Case{"pa.ply", "ply", 1}, Case{"p.obj", "obj", 1},
                        Case{"p.dae", "collada", 0.001f},  // assimp writes <unit meter="1">
                        Case{"p.stl", "stl", 1}, Case{"p.gltf", "gltf2", 0.001f},
                        Case{"p.glb", "glb2", 0.001f}, Case{"p.3mf", "3mf", 1}}) {
    SCOPED_TRACE(c.file);
    reexport(src, dir / c.file, c.format, c.scale);
    const auto r = import(dir / c.file);
    EXPECT_LT((r.mesh.extent() - kPanel).cwiseAbs().maxCoeff(), 1e-3) << r.unit_note;
    EXPECT_EQ(r.mesh.faces.size(), 1150u);
  }
}

TEST(Import, IgesWrittenFromTheStep) {
  test::TempDir dir;
  STEPControl_Reader reader;
  ASSERT_EQ(reader.ReadFile(data("o2ac/02-PANEL.step").c_str()), IFSelect_RetDone);
  reader.TransferRoots();
  IGESControl_Controller::Init();
  IGESControl_Writer writer("MM", 1);  // B-rep mode
  writer.AddShape(reader.OneShape());
  writer.ComputeModel();
  ASSERT_TRUE(writer.Write((dir / "panel.igs").c_str()));
  const auto r = import(dir / "panel.igs");
  EXPECT_EQ(r.reader, "opencascade");
  EXPECT_LT((r.mesh.extent() - kPanel).cwiseAbs().maxCoeff(), 0.02);
}

TEST(Import, UnitsAutoGuessDeclaredAndOverride) {
  test::TempDir dir;
  auto panel = import(data("o2ac/02-PANEL.stl")).mesh;
  panel.scale(0.001f);  // the same part written in metres
  io::write_mesh(dir / "panel_m.stl", panel);
  const auto guessed = import(dir / "panel_m.stl");
  EXPECT_EQ(guessed.unit, Unit::Metre);
  EXPECT_EQ(guessed.unit_source, "guess");
  EXPECT_LT((guessed.mesh.extent() - kPanel).cwiseAbs().maxCoeff(), 1e-3);
  cad::ImportSettings inch;
  inch.unit = Unit::Inch;
  EXPECT_NEAR(import(data("o2ac/02-PANEL.stl"), inch).mesh.extent().x(), 70 * 25.4, 1e-2);

  // COLLADA declaring millimetres: the declaration wins over the guess and is not applied twice.
  std::string dae = test::read_bytes(data("o2ac/04_37D-GEARMOTOR-50-70.dae"));
  const auto at = dae.find("<asset>");
  ASSERT_NE(at, std::string::npos);
  dae.insert(at + 7, "<unit name=\"millimeter\" meter=\"0.001\"/>");
  test::write_text(dir / "gm_mm.dae", dae);
  const auto declared = import(dir / "gm_mm.dae");
  EXPECT_EQ(declared.unit_source, "file");
  EXPECT_NEAR(declared.mesh.extent().z(), 81.7, 0.05);
}

TEST(Import, SelectsAPartByName) {
  test::TempDir dir;
  test::write_text(
      dir / "two.obj",
      "o small\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n"
      "o big\nv 10 0 0\nv 15 0 0\nv 10 5 0\nv 10 0 5\nf 5 7 6\nf 5 6 8\nf 6 7 8\nf 5 8 7\n");
  cad::ImportSettings s;
  s.unit = Unit::Millimetre;
  EXPECT_NEAR(import(dir / "two.obj", s).mesh.extent().x(), 15.0, 1e-6);  // merged
  s.part = "big";
  const auto big = import(dir / "two.obj", s);
  EXPECT_NEAR(big.mesh.extent().x(), 5.0, 1e-6);
  EXPECT_EQ(big.mesh.faces.size(), 4u);
  EXPECT_EQ(big.parts.size(), 2u);
  s.part = "nope";
  try {
    import(dir / "two.obj", s);
    FAIL() << "unknown part accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("big"), std::string::npos) << "lists the parts";
  }
}

TEST(Import, SelectsAStepPartByName) {
  // A two-part STEP file written through OpenCASCADE's XDE with product names.
  test::TempDir dir;
  Handle(TDocStd_Document) doc;
  XCAFApp_Application::GetApplication()->NewDocument("MDTV-XCAF", doc);
  const Handle(XCAFDoc_ShapeTool) tool = XCAFDoc_DocumentTool::ShapeTool(doc->Main());
  TDataStd_Name::Set(tool->AddShape(BRepPrimAPI_MakeBox(gp_Pnt(0, 0, 0), 4, 5, 6).Shape()),
                     "small_box");
  TDataStd_Name::Set(tool->AddShape(BRepPrimAPI_MakeBox(gp_Pnt(20, 0, 0), 10, 10, 10).Shape()),
                     "big_box");
  STEPCAFControl_Writer writer;
  ASSERT_TRUE(writer.Transfer(doc, STEPControl_AsIs));
  ASSERT_EQ(writer.Write((dir / "two.step").c_str()), IFSelect_RetDone);
  cad::ImportSettings s;
  EXPECT_NEAR(import(dir / "two.step", s).mesh.extent().x(), 30.0, 1e-4);  // merged
  s.part = "small_box";
  const auto small = import(dir / "two.step", s);
  EXPECT_LT((small.mesh.extent() - Eigen::Vector3f(4, 5, 6)).cwiseAbs().maxCoeff(), 1e-4);
  EXPECT_NEAR(small.repair.volume_mm3, 120.0, 1e-3);
  s.part = "no_such_box";
  EXPECT_THROW(import(dir / "two.step", s), Error);
}

TEST(Import, BadFilesGiveOneClearError) {
  test::TempDir dir;
  const std::string stl = test::read_bytes(data("o2ac/02-PANEL.stl"));
  const std::string step = test::read_bytes(data("o2ac/02-PANEL.step"));
  test::write_text(dir / "trunc.stl", stl.substr(0, 1000));
  test::write_text(dir / "trunc.step", step.substr(0, step.size() / 2));
  test::write_text(dir / "garbage.obj", std::string("\x01\x02garbage\xff\xfe not an obj"));
  test::write_text(dir / "garbage.ply",
                   "ply\nformat ascii 1.0\nelement vertex 3\nend_header\n1 2\n");
  test::write_text(dir / "garbage.step", "ISO-10303-21;\nHEADER;\nthis is not step\n");
  test::write_text(dir / "empty.stl", "");
  test::write_text(dir / "nan.obj", "v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  test::write_text(dir / "flat.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n");
  for (const char* f : {"trunc.stl", "trunc.step", "garbage.obj", "garbage.ply", "garbage.step",
                        "empty.stl", "nan.obj", "flat.obj", "missing.stl"}) {
    SCOPED_TRACE(f);
    try {
      import(dir / f);
      FAIL() << "accepted a bad file";
    } catch (const Error& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(f), std::string::npos) << "names the file: " << what;
      EXPECT_EQ(what.find('\n'), std::string::npos) << "one line: " << what;
    }
  }
}
