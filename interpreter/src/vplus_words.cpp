// The inventory of V+ words asimov does not simulate (dialect §13). Sources: the V+ Language
// Reference Guide and Operating System Reference Guide (v17) keyword lists.
#include "vplus_words.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <string>

namespace asimov::interpreter {
namespace {

using enum WordKind;
using enum Support;

constexpr std::string_view kVision = "vision (AdeptVision) is not simulated";
constexpr std::string_view kNetwork = "network and serial I/O are not simulated";
constexpr std::string_view kHardware = "the controller's hardware is not simulated";
constexpr std::string_view kGraphics = "the graphics windows of the controller's terminal are not simulated";
constexpr std::string_view kBelt = "conveyor tracking is not simulated";
constexpr std::string_view kForce = "force sensing is not simulated";
constexpr std::string_view kPendant = "the manual control pendant is not simulated";
constexpr std::string_view kAlter = "real-time path modification is not simulated";
constexpr std::string_view kEvents = "task events are not simulated";
constexpr std::string_view kServo = "the simulated arm reaches its target exactly: servo settling has no effect";
constexpr std::string_view kTerminal = "the controller's terminal settings have no effect in simulation";
constexpr std::string_view kSystem = "the controller's system software is not simulated";
constexpr std::string_view kDisk = "the controller's disk is the host's: use the shell";
constexpr std::string_view kEditor = "the controller's editors are not simulated: edit the file";
constexpr std::string_view kKinematics = "kinematic solutions on request are not simulated";
constexpr std::string_view kTeach = "teaching with the pendant is not simulated";
constexpr std::string_view kBrake = "stopping the arm from a program is not simulated";
constexpr std::string_view kPack = "packed binary strings beyond $LNGB, $INTB and $FLTB are not simulated";
constexpr std::string_view kDevices = "devices of the controller (DEVICE, SETDEVICE) are not simulated";
constexpr std::string_view kMulti = "one robot is simulated";

constexpr VplusWord kWords[] = {
    // --- program instructions --------------------------------------------------------------
    {"ALTER", instruction, refused, kAlter},
    {"ALTOFF", instruction, refused, kAlter},
    {"ALTON", instruction, refused, kAlter},
    {"BITS", instruction, refused, "setting a group of signals with BITS is not simulated: use SIGNAL"},
    {"BRAKE", instruction, refused, kBrake},
    {"CALIBRATE", instruction, refused, "the simulated arm is calibrated"},
    {"CLEAR.EVENT", instruction, refused, kEvents},
    {"COARSE", instruction, no_effect, kServo},
    {"CPOFF", instruction, refused, "CPOFF is not simulated: use DISABLE CP"},
    {"CPON", instruction, refused, "CPON is not simulated: use ENABLE CP"},
    {"DEFBUF", instruction, no_effect, kTerminal},
    {"ESTOP", instruction, refused, kBrake},
    {"FCMND", instruction, refused, kNetwork},  // the I/O statement's own message (dialect §7a)
    {"FINE", instruction, no_effect, kServo},
    {"FOPEN", instruction, refused, kNetwork},
    {"FSEEK", instruction, refused, "random access to files is not simulated"},
    {"FSET", instruction, refused, kNetwork},
    {"GARC", instruction, refused, kGraphics},
    {"GCLEAR", instruction, refused, kGraphics},
    {"GCLIP", instruction, refused, kGraphics},
    {"GCOLOR", instruction, refused, kGraphics},
    {"GCOPY", instruction, refused, kGraphics},
    {"GFLOOD", instruction, refused, kGraphics},
    {"GICON", instruction, refused, kGraphics},
    {"GLINE", instruction, refused, kGraphics},
    {"GLINES", instruction, refused, kGraphics},
    {"GLOGICAL", instruction, refused, kGraphics},
    {"GPANEL", instruction, refused, kGraphics},
    {"GPOINT", instruction, refused, kGraphics},
    {"GRECTANGLE", instruction, refused, kGraphics},
    {"GSCAN", instruction, refused, kGraphics},
    {"GSLIDE", instruction, refused, kGraphics},
    {"GTEXT", instruction, refused, kGraphics},
    {"GTEXTURE", instruction, refused, kGraphics},
    {"GTRANS", instruction, refused, kGraphics},
    {"GTYPE", instruction, refused, kGraphics},
    {"KEYMODE", instruction, no_effect, kPendant},
    {"MC", instruction, refused, "monitor commands from a program (MC) are not simulated"},
    {"MCS", instruction, refused, "monitor commands from a program (MCS) are not simulated"},
    {"MOVEF", instruction, refused, "MOVEF (door-to-door motion of SCARA arms) is not simulated"},
    {"MOVESF", instruction, refused, "MOVESF (door-to-door motion of SCARA arms) is not simulated"},
    {"NONULL", instruction, no_effect, kServo},
    {"NOOVERLAP", instruction, no_effect, "joint overlap is not checked in simulation"},
    {"NULL", instruction, no_effect, kServo},
    {"OVERLAP", instruction, no_effect, "joint overlap is not checked in simulation"},
    {"PACK", instruction, refused, kPack},
    {"PANIC", instruction, refused, kBrake},
    {"PDNT.CLEAR", instruction, refused, kPendant},
    {"PDNT.WRITE", instruction, refused, kPendant},
    {"PROCEED", instruction, refused, "resuming another task from a program is not simulated"},
    {"RESET", instruction, refused, "RESET (all outputs off) is not simulated: use SIGNAL"},
    {"RETRY", instruction, refused, "resuming another task from a program is not simulated"},
    {"RETURNE", instruction, refused, "RETURNE is not simulated: use RETURN"},
    {"RUNSIG", instruction, refused, "RUNSIG is not simulated: use SIGNAL"},
    {"SELECT", instruction, refused, kMulti},
    {"SET.EVENT", instruction, refused, kEvents},
    {"SETBELT", instruction, refused, kBelt},
    {"SETDEVICE", instruction, refused, kDevices},
    {"SOLVE.ANGLES", instruction, refused, kKinematics},
    {"SOLVE.TRANS", instruction, refused, kKinematics},
    {"SPIN", instruction, refused, "SPIN (continuous joint rotation) is not simulated"},
    {"TEACH", instruction, refused, kTeach},
    {"VDEF.AOI", instruction, refused, kVision},
    {"VDEF.CONVOLVE", instruction, refused, kVision},
    {"VDEF.FONT", instruction, refused, kVision},
    {"VDEF.LUT", instruction, refused, kVision},
    {"VDEF.MORPH", instruction, refused, kVision},
    {"VDEF.SUBPROTO", instruction, refused, kVision},
    {"VDEF.TRANS", instruction, refused, kVision},
    {"VDELETE", instruction, refused, kVision},
    {"VDISPLAY", instruction, refused, kVision},
    {"VEDGE", instruction, refused, kVision},
    {"VFIND.ARC", instruction, refused, kVision},
    {"VFIND.LINE", instruction, refused, kVision},
    {"VFIND.POINT", instruction, refused, kVision},
    {"VHISTOGRAM", instruction, refused, kVision},
    {"VLOAD", instruction, refused, kVision},
    {"VLOCATE", instruction, refused, kVision},
    {"VOCR", instruction, refused, kVision},
    {"VPICTURE", instruction, refused, kVision},
    {"VPUTCAL", instruction, refused, kVision},
    {"VRULER", instruction, refused, kVision},
    {"VSELECT", instruction, refused, kVision},
    {"VSTORE", instruction, refused, kVision},
    {"VSUBTRACT", instruction, refused, kVision},
    {"VTHRESHOLD", instruction, refused, kVision},
    {"VTRAIN", instruction, refused, kVision},
    {"VWAIT", instruction, refused, kVision},
    {"VWINDOW", instruction, refused, kVision},
    {"WINDOW", instruction, refused, kBelt},
    // --- functions -------------------------------------------------------------------------
    {"$DBLB", function, refused, kPack},
    {"$DEFAULT", function, refused, kDisk},
    {"$ID", function, refused, kSystem},
    {"$SYMBOL", function, refused, "symbol lookup by address is not simulated"},
    {"$TRANSB", function, refused, kPack},
    {"$TRUNCATE", function, refused, kPack},
    {"$UNPACK", function, refused, kPack},
    {"ACCEL", function, refused, "reading the acceleration settings (ACCEL(select)) is not simulated"},
    {"BELT", function, refused, kBelt},
    {"BITS", function, refused, "reading a group of signals with BITS is not simulated: use SIG"},
    {"BSTATUS", function, refused, kBelt},
    {"CAS", function, refused, kEvents},
    {"CONFIG", function, refused, kSystem},
    {"DBLB", function, refused, kPack},
    {"DEVICE", function, refused, kDevices},
    {"DURATION", function, refused, "reading the DURATION setting is not simulated"},
    {"FREE", function, refused, kSystem},
    {"GETEVENT", function, refused, kEvents},
    {"HOUR.METER", function, refused, kHardware},
    {"ID", function, refused, kSystem},
    {"LATCH", function, refused, "latched positions are not simulated"},
    {"LATCHED", function, refused, "latched positions are not simulated"},
    {"NETWORK", function, refused, kNetwork},
    {"NORM", function, refused, "NORM is not simulated"},
    {"OUTSIDE", function, refused, "OUTSIDE is not simulated"},
    {"PENDANT", function, refused, kPendant},
    {"POS", function, refused, "POS is not simulated"},
    {"SIG.INS", function, refused, kHardware},
    {"SOLVE.FLAGS", function, refused, kKinematics},
    {"TIME", function, refused, "TIME (a date or time packed from a string) is not simulated"},
    {"TPS", function, refused, kSystem},
    {"TRANSB", function, refused, kPack},
    {"VFEATURE", function, refused, kVision},
    {"VQUEUE", function, refused, kVision},
    {"VSTATUS", function, refused, kVision},
    {"WINDOW", function, refused, kBelt},
    // --- monitor commands ------------------------------------------------------------------
    {"CD", monitor, refused, kDisk},
    {"COMMANDS", monitor, refused, "command programs are not simulated"},
    {"COPY", monitor, refused, kEditor},
    {"CYCLE.END", monitor, refused, "tasks run from programs only (EXECUTE n)"},
    {"DEFAULT", monitor, refused, kDisk},
    {"DELETEL", monitor, refused, "DELETEL is not simulated: use DELETE"},
    {"DELETEM", monitor, refused, "modules are not simulated"},
    {"DELETEP", monitor, refused, "DELETEP is not simulated: use DELETE"},
    {"DELETER", monitor, refused, "DELETER is not simulated: use DELETE"},
    {"DELETES", monitor, refused, "DELETES is not simulated: use DELETE"},
    {"DISABLE", monitor, refused, "switches are set from programs in simulation"},
    {"EDIT", monitor, refused, kEditor},
    {"ENABLE", monitor, refused, "switches are set from programs in simulation"},
    {"ESTOP", monitor, refused, kBrake},
    {"FCOPY", monitor, refused, kDisk},
    {"FDELETE", monitor, refused, kDisk},
    {"FDIRECTORY", monitor, refused, kDisk},
    {"FLIST", monitor, refused, kDisk},
    {"FRENAME", monitor, refused, kDisk},
    {"FSET", monitor, refused, kNetwork},
    {"ID", monitor, refused, kSystem},
    {"IO", monitor, refused, "the signals are shown in the report (docs/cli.md)"},
    {"KILL", monitor, refused, "tasks run from programs only (EXECUTE n)"},
    {"LIST", monitor, refused, "LIST is not simulated: use LISTL, LISTP, LISTR, LISTS"},
    {"MDIRECTORY", monitor, refused, "modules are not simulated"},
    {"MODULE", monitor, refused, "modules are not simulated"},
    {"NET", monitor, refused, kNetwork},
    {"PANIC", monitor, refused, kBrake},
    {"PARAMETER", monitor, refused, "parameters are set from programs in simulation"},
    {"PRIME", monitor, refused, "PRIME is not simulated: use EXECUTE"},
    {"RENAME", monitor, refused, kEditor},
    {"RESET", monitor, refused, "RESET (all outputs off) is not simulated"},
    {"SEE", monitor, refused, kEditor},
    {"SELECT", monitor, refused, kMulti},
    {"SIGNAL", monitor, refused, "signals are set from programs in simulation"},
    {"SRV.NET", monitor, refused, kNetwork},
    {"SRV.RESET", monitor, refused, kNetwork},
    {"STACK", monitor, refused, kSystem},
    {"STOREM", monitor, refused, "modules are not simulated: use STORE"},
    {"STOREP", monitor, refused, "STOREP is not simulated: use STORE"},
    {"STORER", monitor, refused, "STORER is not simulated: use STORE"},
    {"STORES", monitor, refused, "STORES is not simulated: use STORE"},
    {"SWITCH", monitor, refused, "switches are read from programs in simulation"},
    {"TEACH", monitor, refused, kTeach},
    {"TESTP", monitor, refused, "TESTP is not simulated: use STATUS"},
    {"TIME", monitor, refused, "the controller's clock is the host's"},
    {"TOOL", monitor, refused, "TOOL is set from programs in simulation"},
    {"WAIT", monitor, refused, "WAIT is a program instruction in simulation"},
    {"WATCH", monitor, refused, "the program debugger is not simulated"},
    // --- system switches -------------------------------------------------------------------
    {"AUTO.POWER.OFF", switch_, refused, kHardware},
    {"BELT", switch_, refused, kBelt},
    {"DECEL.100", switch_, refused, "DECEL.100 is not simulated"},
    {"FORCE", switch_, refused, kForce},
    {"INTERACTIVE", switch_, no_effect, kTerminal},
    {"MESSAGES", switch_, no_effect, kTerminal},
    {"MONITORS", switch_, no_effect, kTerminal},
    {"NETWORK", switch_, refused, kNetwork},
    {"OBSTACLE", switch_, refused, "obstacles of the controller are not simulated: the cell's bodies are"},
    {"ROBOT", switch_, refused, kMulti},
    {"SCALE.ACCEL.ROT", switch_, refused, "SCALE.ACCEL.ROT is not simulated"},
    {"SET.SPEED", switch_, no_effect, kPendant},
    {"TRACE", switch_, no_effect, "tracing of steps is not simulated: use asimov run --trace"},
    {"UPPER", switch_, no_effect, kTerminal},
    {"VFEEDTHRU", switch_, refused, kVision},
    {"VISION", switch_, refused, kVision},
    // --- system parameters -----------------------------------------------------------------
    {"BELT.MODE", parameter, refused, kBelt},
    {"KERMIT.RETRY", parameter, refused, kNetwork},
    {"KERMIT.TIMEOUT", parameter, refused, kNetwork},
    {"SCREEN.TIMEOUT", parameter, no_effect, kTerminal},
    {"TERMINAL", parameter, no_effect, kTerminal},
    {"VTIMEOUT", parameter, refused, kVision},
};

std::string upper(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return out;
}

}  // namespace

std::span<const VplusWord> vplus_words() { return kWords; }

const VplusWord* vplus_word(std::string_view name, WordKind kind) {
  const std::string key = upper(name);
  const auto it = std::find_if(std::begin(kWords), std::end(kWords),
                               [&](const VplusWord& w) { return w.kind == kind && w.name == key; });
  return it == std::end(kWords) ? nullptr : &*it;
}

std::string vplus_refusal(const VplusWord& w) { return std::string(w.name) + ": " + std::string(w.reason); }

}  // namespace asimov::interpreter
