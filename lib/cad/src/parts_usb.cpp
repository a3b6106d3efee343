// NIST Assembly Task Board 1 USB-A plug and receptacle (USB 2.0 plug shell 12.0 x 4.5 mm).
#include "laserfit/core/error.hpp"
#include "occt_shapes.hpp"
#include "parts.hpp"

namespace laserfit::cad {

std::vector<PartShape> build_usb_a(const Params& p) {
  using namespace shapes;
  const double W = p.at("shell_width"), H = p.at("shell_height"), Ls = p.at("shell_length");
  const double t = p.at("shell_thickness"), c = p.at("clearance"), D = p.at("socket_depth");
  const double bw = p.at("body_width"), bh = p.at("body_height"), bl = p.at("body_length");
  if (bw <= W || bh <= H) throw Error("usb_a: the overmould must be larger than the shell");
  const double iw = W / 2 - t, ih = H / 2 - t;  // inner half sizes of the shell

  // Plug: front of the shell at z = 0, +z out of the plug (insertion direction), x across the
  // 12 mm width, y across the 4.5 mm height. The contact insulator fills the lower part of the
  // shell; the two latch windows on the top face break the 180 degree symmetry further.
  TopoDS_Shape plug =
      cut(box(-W / 2, -H / 2, -Ls, W / 2, H / 2, 0), box(-iw, -ih, -Ls + 1.0, iw, ih, 0.1));
  plug = fuse(plug, box(-iw, -ih, -Ls + 0.5, iw, -ih + 1.95, -0.6));
  for (double sx : {-1.0, 1.0})
    plug = cut(plug, box(sx * 3.25 - 1.0, ih - 0.1, -4.5, sx * 3.25 + 1.0, H / 2 + 0.1, -3.0));
  plug = fuse(plug, box(-bw / 2, -bh / 2, -Ls - bl, bw / 2, bh / 2, -Ls + 0.5));

  // Receptacle: mouth of the opening at z = 0 on the front of a task-board plate, +z into the
  // socket. Opening = shell + clearance; the tongue sits in the upper part, above the plug's
  // insulator, as in a real USB-A socket.
  const double ow = (W + c) / 2, oh = (H + c) / 2, wall = 0.5, plate = p.at("plate_size") / 2;
  TopoDS_Shape sock = box(-plate, -plate, 0, plate, plate, 1.5);
  sock = fuse(sock, box(-ow - wall, -oh - wall, 0, ow + wall, oh + wall, D + wall));
  sock = cut(sock, box(-ow, -oh, -0.1, ow, oh, D));
  const double tongue_lo = -ih + 1.95 + 0.25, tongue_hi = tongue_lo + 1.75;
  if (tongue_hi > oh - 0.2) throw Error("usb_a: shell_height too small for the socket tongue");
  sock = fuse(sock, box(-iw + 0.3, tongue_lo, 1.5, iw - 0.3, tongue_hi, D + 0.01));

  return {{"usb_a_plug",
           "origin at the centre of the shell's front opening; z = insertion direction; x across "
           "the 12 mm width; y across the 4.5 mm height",
           plug},
          {"usb_a_receptacle",
           "origin at the centre of the socket mouth on the plate's front face; z into the socket; "
           "x across the width",
           sock}};
}

}  // namespace laserfit::cad
