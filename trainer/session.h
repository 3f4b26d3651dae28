// Sessions: what a trainee did, recorded so that it can be replayed bit-identically and
// scored. A JSON Lines file, written as it goes: a header line, input lines when the
// handle inputs change, checkpoint lines once per simulated second (state hash, flush),
// optional event lines, and an end line with the final state hash and a summary.
// Format: docs/file-formats.md ("Sessions").
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/handle_input.h"
#include "trainer/assist_input.h"

struct gzFile_s;  // zlib's gzFile (the compressed session writer)

namespace colosim {

constexpr const char* kSessionFormat = "colosim-session";
constexpr int kSessionVersion = 1;

/// Everything needed to replay a session, besides its inputs.
struct SessionHeader {
  std::string scenario;         ///< scenario id: a shipped name or an absolute path
  uint64_t scenario_hash = 0;   ///< FNV-1a of the scenario file
  uint64_t params_hash = 0;     ///< FNV-1a of the parameter file
  /// The parameter file the run used instead of the scenario's (`colosim run --params`,
  /// e.g. an identified model), as an absolute path; empty: the scenario's own.
  std::string params;
  uint64_t anatomy_hash = 0;    ///< FNV-1a of the anatomy file
  /// FNV-1a of the scope design file (optional key scope_hash, 0: not recorded, sessions
  /// written before scope designs).
  uint64_t scope_hash = 0;
  /// The scope design the run used instead of the scenario's (useScopeDesign), as an
  /// absolute path; empty: the scenario's own.
  std::string scope;
  std::string colosim_version;  ///< version of the build that recorded it
  double dt_s = 1e-3;           ///< time step [s]
  int seed = 0;
  std::string mode = "scripted";  ///< "scripted" (colosim run) or "interactive" (colosim train)
  /// The patient position the trainee chose in place of the scenario's (colosim train's
  /// start screen; optional key); empty: the scenario's own.
  std::string patient_position;
};

/// The handle input from `step` on (steps are counted from 0; step k runs from
/// k dt to (k + 1) dt).
struct SessionInput {
  long step = 0;
  HandleInput input;
  int line = 0;  ///< line in the file (1-based)
};

/// The assistance (an assistant's abdominal pressure, the patient's position) from `step`
/// on; none before the first such line.
struct SessionAssist {
  long step = 0;
  AssistInput assist;
  int line = 0;
};

/// Something that happened after `step` steps (for example "solver_limited").
struct SessionEvent {
  long step = 0;
  std::string name;
  std::string detail;
  int line = 0;
};

/// The state hash after `step` steps, written once per simulated second.
struct SessionCheckpoint {
  long step = 0;
  uint64_t state_hash = 0;
  int line = 0;
};

struct Session {
  std::string file;
  SessionHeader header;
  std::vector<SessionInput> inputs;        ///< steps strictly increasing; the first at step 0
  std::vector<SessionEvent> events;
  std::vector<SessionAssist> assists;      ///< steps strictly increasing
  std::vector<SessionCheckpoint> checkpoints;
  /// Steps to replay: the end line's count, or for a truncated file the last step a
  /// complete line vouches for.
  long steps = 0;
  bool complete = false;          ///< the end line is present
  uint64_t final_state_hash = 0;  ///< from the end line (complete only)
  nlohmann::json summary;         ///< from the end line (complete only), an object
  bool truncated = false;         ///< no end line: only a prefix can be replayed
  std::string message;            ///< why it is truncated, naming the file and line
  int lines = 0;                  ///< complete lines read
};

/// Reads a session file strictly. Wrong format or version, unknown or missing keys, NaN,
/// non-increasing steps, out-of-range inputs, lines after the end line: InputError
/// naming the file and line. A file without its end line (a crash), or whose last line
/// is cut off, gives the replayable prefix with truncated = true and a message.
/// A file cut before its header is complete is an InputError (nothing to replay).
/// A gzip-compressed session (NAME.jsonl.gz) is read the same way; a corrupt gzip stream
/// is an InputError naming the file.
Session readSession(const std::string& path);
/// The header and the end line only (the summary, the final state hash, the steps), the
/// lines between skipped unread: for a session's summary without the cost of reading it
/// (the expert sessions of the score card, 240,000 lines for free_insertion). What is
/// between is not checked; readSession checks it.
Session readSessionEnds(const std::string& path);
/// The same from text in memory; `file` names it in messages.
Session parseSession(const std::string& text, const std::string& file);

/// The gzip suffix of a compressed session's name (NAME.jsonl.gz): SessionWriter
/// compresses a path ending in it; readSession reads either.
inline constexpr const char* kGzipSuffix = ".gz";
/// `path` without its gzip suffix when it has one (`*compressed` says whether it had).
std::string withoutGzipSuffix(const std::string& path, bool* compressed = nullptr);

/// 16 lowercase hex digits.
std::string hashToHex(uint64_t h);

/// Writes a session as it goes. Lines are flushed at every checkpoint (once per
/// simulated second) and at events and the end, so a crash loses at most the last second.
/// A path ending in ".gz" is written gzip-compressed (readSession reads it; each flush is
/// a zlib sync point, so a crash leaves a readable prefix there too).
class SessionWriter {
 public:
  /// Opens (creates or truncates) `path` and writes the header. Validate every input
  /// before constructing one: the file is replaced. std::runtime_error when it cannot be
  /// opened.
  SessionWriter(const std::string& path, const SessionHeader& header);
  ~SessionWriter();
  SessionWriter(const SessionWriter&) = delete;
  SessionWriter& operator=(const SessionWriter&) = delete;

  /// The input of step `step` (called before that step, steps in order): written
  /// only when it differs from the previous one.
  void input(long step, const HandleInput& in);
  /// The assistance from step `step` on (called before that step): written only when it
  /// differs from the last one (none at first); flushed at once.
  void assist(long step, const AssistInput& a);
  /// An event after `steps_done` steps; flushed at once.
  void event(long steps_done, const std::string& name, const std::string& detail = "");
  /// True when a checkpoint is due after `steps_done` steps (once per simulated second).
  bool checkpointDue(long steps_done) const { return steps_done > 0 && steps_done % checkpoint_steps_ == 0; }
  /// Writes the state hash after `steps_done` steps and flushes.
  void checkpoint(long steps_done, uint64_t state_hash);
  /// Writes the end line and closes the file. `summary` must be a JSON object.
  void end(long steps_done, uint64_t state_hash, const nlohmann::json& summary);

  long checkpointSteps() const { return checkpoint_steps_; }

 private:
  void writeLine(const nlohmann::json& j);
  void flush();
  bool close();  ///< false when the last writes failed
  bool isOpen() const { return f_ != nullptr || gz_ != nullptr; }
  std::string path_;
  std::FILE* f_ = nullptr;        ///< a plain file, or
  ::gzFile_s* gz_ = nullptr;      ///< a gzip-compressed one
  SessionHeader header_;
  long checkpoint_steps_ = 1000;
  long last_step_ = -1;
  bool have_input_ = false;
  HandleInput last_input_;
  AssistInput last_assist_;
  long last_assist_step_ = -1;
};

}  // namespace colosim
