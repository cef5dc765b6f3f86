// occt_read.cpp
// A test oracle: reads a STEP or IGES file with OpenCASCADE (STEPControl_Reader /
// IGESControl_Reader, as a CAD program built on OCCT does), transfers every root,
// and prints every edge's 3D curve and every face's surface, evaluated by OCCT:
//
//   occt_read FILE NC NS
//   curve K TYPE DEGREE POLES RATIONAL PERIODIC FIRST LAST    then NC lines "x y z" at
//                                                            FIRST + (LAST-FIRST) i/(NC-1)
//   surface K TYPE DU DV NU NV RATIONAL UPER VPER U1 U2 V1 V2 then NS*NS lines "x y z",
//                                                            u index slowest, ends included
//   end CURVES SURFACES
//
// Exit status 0 when the file was read and transferred, 1 otherwise (message on
// stderr). bsfit's tests compare these points with bsfit's own evaluation.
#include <BRep_Tool.hxx>
#include <Geom_BSplineCurve.hxx>
#include <Geom_BSplineSurface.hxx>
#include <Geom_Curve.hxx>
#include <Geom_Surface.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <IGESControl_Reader.hxx>
#include <Interface_Static.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Message_PrinterOStream.hxx>
#include <STEPControl_Reader.hxx>
#include <Standard_Failure.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Shape.hxx>
#include <XSControl_Reader.hxx>
#include <gp_Pnt.hxx>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>

static bool ends_with(const char *s, const char *ext) {
  size_t n = strlen(s), k = strlen(ext);
  return n >= k && strcasecmp(s + n - k, ext) == 0;
}

static void print_point(const gp_Pnt &P) { printf("%.17g %.17g %.17g\n", P.X(), P.Y(), P.Z()); }

static void print_curve(int k, const Handle(Geom_Curve) &c, double first, double last, int nc) {
  Handle(Geom_BSplineCurve) b = Handle(Geom_BSplineCurve)::DownCast(c);
  printf("curve %d %s %d %d %d %d %.17g %.17g\n", k, c->DynamicType()->Name(),
         b.IsNull() ? -1 : b->Degree(), b.IsNull() ? -1 : b->NbPoles(),
         b.IsNull() ? -1 : (int)b->IsRational(), (int)c->IsPeriodic(), first, last);
  for (int i = 0; i < nc; i++) print_point(c->Value(first + (last - first) * i / (nc - 1)));
}

static void print_surface(int k, const Handle(Geom_Surface) &s, int ns) {
  Handle(Geom_BSplineSurface) b = Handle(Geom_BSplineSurface)::DownCast(s);
  double u1, u2, v1, v2;
  s->Bounds(u1, u2, v1, v2);
  printf("surface %d %s %d %d %d %d %d %d %d %.17g %.17g %.17g %.17g\n", k,
         s->DynamicType()->Name(), b.IsNull() ? -1 : b->UDegree(), b.IsNull() ? -1 : b->VDegree(),
         b.IsNull() ? -1 : b->NbUPoles(), b.IsNull() ? -1 : b->NbVPoles(),
         b.IsNull() ? -1 : (int)(b->IsURational() || b->IsVRational()), (int)s->IsUPeriodic(),
         (int)s->IsVPeriodic(), u1, u2, v1, v2);
  for (int i = 0; i < ns; i++)
    for (int j = 0; j < ns; j++)
      print_point(s->Value(u1 + (u2 - u1) * i / (ns - 1), v1 + (v2 - v1) * j / (ns - 1)));
}

int main(int argc, char **argv) {
  if (argc != 4) {
    fprintf(stderr, "usage: occt_read FILE.(step|stp|iges|igs) NC NS\n");
    return 2;
  }
  int nc = atoi(argv[2]), ns = atoi(argv[3]);
  if (nc < 2 || ns < 2) {
    fprintf(stderr, "occt_read: NC and NS must be >= 2\n");
    return 2;
  }
  // OCCT's messages go to stdout by default: send them to stderr, stdout is the data
  Message::DefaultMessenger()->RemovePrinters(STANDARD_TYPE(Message_PrinterOStream));
  Message::DefaultMessenger()->AddPrinter(new Message_PrinterOStream("/dev/stderr", false));
  try {
    std::unique_ptr<XSControl_Reader> r;
    if (ends_with(argv[1], ".step") || ends_with(argv[1], ".stp")) {
      r.reset(new STEPControl_Reader);
    } else {
      r.reset(new IGESControl_Reader);
      // keep each entity 126 one edge: by default the IGES reader cuts B-splines at
      // their C0 knots (a degree-1 curve becomes one edge per segment), which changes
      // nothing in the geometry but breaks the one-to-one comparison
      Interface_Static::SetIVal("read.iges.bspline.continuity", 0);
    }
    if (r->ReadFile(argv[1]) != IFSelect_RetDone) {
      fprintf(stderr, "occt_read: %s: cannot read\n", argv[1]);
      return 1;
    }
    int roots = r->TransferRoots();
    if (roots < 1) {
      fprintf(stderr, "occt_read: %s: nothing transferred\n", argv[1]);
      return 1;
    }
    TopoDS_Shape shape = r->OneShape();
    int ncurves = 0, nsurfaces = 0;
    for (TopExp_Explorer ex(shape, TopAbs_FACE); ex.More(); ex.Next()) {
      Handle(Geom_Surface) s = BRep_Tool::Surface(TopoDS::Face(ex.Current()));
      if (!s.IsNull()) print_surface(++nsurfaces, s, ns);
    }
    for (TopExp_Explorer ex(shape, TopAbs_EDGE, TopAbs_FACE); ex.More(); ex.Next()) {
      double first, last;
      Handle(Geom_Curve) c = BRep_Tool::Curve(TopoDS::Edge(ex.Current()), first, last);
      if (!c.IsNull()) print_curve(++ncurves, c, first, last, nc);
    }
    printf("end %d %d\n", ncurves, nsurfaces);
  } catch (const Standard_Failure &f) {
    fprintf(stderr, "occt_read: %s: OCCT exception %s\n", argv[1], f.GetMessageString());
    return 1;
  }
  return 0;
}
