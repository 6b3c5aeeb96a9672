// raster view: the step cursor and the script language on their own, then the viewer run headless
// (SDL's offscreen driver) against direct renders of the same scenes through the library: its
// screenshots must be the framebuffer, byte for byte, at every step. The viewer in a real X window
// is tests/viewer_xvfb_test.sh.
#include "view/viewer.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <initializer_list>
#include <iterator>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "commands.hpp"
#include "raster/image_io.hpp"
#include "raster/scenes.hpp"
#include "raster/trace_format.hpp"
#include "view/camera.hpp"
#include "view/compare_views.hpp"
#include "view/overlay.hpp"
#include "view/playback.hpp"
#include "view/trace_views.hpp"

namespace raster::tools {
namespace {

constexpr uint32_t kWidth = 320, kHeight = 180;
constexpr uint32_t kParticles = 2000;  // enough to see, quick to replay at every step

void expectInvalidArgument(const std::function<void()>& f, std::initializer_list<std::string> parts) {
    try {
        f();
        ADD_FAILURE() << "expected Error(InvalidArgument), nothing was thrown";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::InvalidArgument) << e.what();
        const std::string message = e.what();
        for (const std::string& part : parts)
            EXPECT_NE(message.find(part), std::string::npos)
                << "message \"" << message << "\" lacks \"" << part << "\"";
    }
}

// ---- The step cursor ---------------------------------------------------------------------------------

// Where the cursor is, as (draws, primitives) with -1 draws for the whole frame.
std::pair<int64_t, uint64_t> where(const StepCursor& c) {
    return c.whole() ? std::pair<int64_t, uint64_t>{-1, 0}
                     : std::pair<int64_t, uint64_t>{c.draws(), c.primitives()};
}

TEST(StepCursor, PrimitiveStepsWalkEveryPrefixAndBackExactly) {
    StepCursor c;
    c.setShape({2, 0, 3});  // a draw without primitives in the middle
    ASSERT_TRUE(c.whole());
    EXPECT_EQ(c.limit().draws, UINT32_MAX);
    std::vector<std::pair<int64_t, uint64_t>> forward;
    std::vector<Context::StepLimit> limits;
    for (int i = 0; i < 6; ++i) {
        c.nextPrimitive();
        forward.push_back(where(c));
        limits.push_back(c.limit());
    }
    // Draw 1 primitive by primitive, the empty draw in one step, then draw 3.
    const std::vector<std::pair<int64_t, uint64_t>> expected = {{1, 1}, {1, 2}, {2, 0},
                                                                {3, 1}, {3, 2}, {3, 3}};
    EXPECT_EQ(forward, expected);
    EXPECT_EQ(limits[0].draws, 1u);
    EXPECT_EQ(limits[0].primitives, 1u);
    EXPECT_EQ(limits[1].primitives, UINT64_MAX) << "a complete draw runs unlimited, as in the whole frame";
    EXPECT_EQ(limits[4].draws, 3u);
    EXPECT_EQ(limits[4].primitives, 2u);
    c.nextPrimitive();
    EXPECT_EQ(where(c), (std::pair<int64_t, uint64_t>{3, 3})) << "the end of the frame stays put";
    for (int i = 4; i >= 0; --i) {
        c.previousPrimitive();
        EXPECT_EQ(where(c), expected[size_t(i)]) << "step back " << 5 - i;
    }
    c.previousPrimitive();
    EXPECT_EQ(where(c), (std::pair<int64_t, uint64_t>{0, 0}));
    EXPECT_EQ(c.limit().draws, 0u);
    EXPECT_EQ(c.label(), "draw 0 of 3 (cleared targets)");
    c.previousPrimitive();
    EXPECT_EQ(where(c), (std::pair<int64_t, uint64_t>{0, 0}));
}

TEST(StepCursor, DrawStepsFinishOrLeaveTheDraw) {
    StepCursor c;
    c.setShape({2, 5});
    c.nextDraw();
    EXPECT_EQ(where(c), (std::pair<int64_t, uint64_t>{1, 2}));
    EXPECT_EQ(c.label(), "draw 1 of 2, complete (2 primitives)");
    c.nextDraw();
    c.previousDraw();
    EXPECT_EQ(where(c), (std::pair<int64_t, uint64_t>{1, 2}))
        << "forward twice and back once is forward once";
    c.nextPrimitive();
    c.nextPrimitive();
    EXPECT_EQ(c.label(), "draw 2 of 2, primitive 2 of 5");
    c.nextDraw();
    EXPECT_EQ(where(c), (std::pair<int64_t, uint64_t>{2, 5})) << "N inside a draw finishes it";
    c.nextPrimitive();
    c.nextDraw();
    EXPECT_EQ(where(c), (std::pair<int64_t, uint64_t>{2, 5})) << "N at the end stays";
    c.previousPrimitive();
    c.previousDraw();
    EXPECT_EQ(where(c), (std::pair<int64_t, uint64_t>{1, 2}))
        << "P inside a draw goes to the end of the one before";
    c.showAll();
    c.previousDraw();
    EXPECT_EQ(where(c), (std::pair<int64_t, uint64_t>{1, 2}))
        << "P from the whole frame steps back from its end";
    c.showAll();
    c.previousPrimitive();
    EXPECT_EQ(where(c), (std::pair<int64_t, uint64_t>{2, 4}));
    c.showAll();
    EXPECT_EQ(c.label(), "whole frame, 2 draws");
}

// ---- Render progress -------------------------------------------------------------------------------------

RunningRender runningAt(double seconds, uint32_t started, uint32_t finished, uint32_t tilesInDraw,
                        uint32_t tilesFinished, bool solution = false) {
    return {seconds, solution, {started, finished, tilesInDraw, tilesFinished}};
}

TEST(ViewerProgress, TextSaysWhichDrawAndHowManyOfItsTiles) {
    EXPECT_EQ(progressText(RunningRender{}, 2), "rendering... 0.0 s");
    EXPECT_EQ(progressText(runningAt(-1, 0, 0, 0, 0), 2), "rendering... 0.0 s");
    EXPECT_EQ(progressText(runningAt(1.3, 2, 1, 200, 90), 2),
              "rendering... 1.3 s  draw 2 of 2, 45% of its tiles");
    EXPECT_EQ(progressText(runningAt(1.3, 2, 1, 200, 90), 0), "rendering... 1.3 s  draw 2, 45% of its tiles")
        << "total unknown";
    EXPECT_EQ(progressText(runningAt(1.3, 2, 1, 200, 90), 1), "rendering... 1.3 s  draw 2, 45% of its tiles")
        << "a total below the draws seen is stale";
    EXPECT_EQ(progressText(runningAt(0.1, 1, 0, 0, 0), 2), "rendering... 0.1 s  draw 1 of 2, geometry");
    EXPECT_EQ(progressText(runningAt(0.1, 1, 1, 15, 15), 2), "rendering... 0.1 s  draw 1 of 2 done");
    EXPECT_EQ(progressText(runningAt(12, 2, 1, 200, 199), 2),
              "rendering... 12.0 s  draw 2 of 2, 99% of its tiles");
    EXPECT_EQ(progressText(runningAt(12, 2, 1, 200, 200), 2),
              "rendering... 12.0 s  draw 2 of 2, 100% of its tiles");
    EXPECT_EQ(progressText(runningAt(0.4, 1, 0, 240, 0, true), 2),
              "rendering solution... 0.4 s  draw 1 of 2, 0% of its tiles");
}

TEST(ViewerProgress, WorkerReportsTheFramesAndTheSolutionsDraws) {
    // Long enough to be caught part way (a tenth of a second or so a render), short for a test.
    RenderWorker worker("particles", {}, nullptr, SolutionRender{"particles", {}});
    RenderRequest request;
    request.scene = {.width = 1280, .height = 720, .count = 40000};
    request.solution = true;
    EXPECT_FALSE(worker.running().has_value()) << "idle";
    const uint64_t id = worker.request(request);
    std::shared_ptr<RenderedFrame> frame;
    uint32_t frame_draws_seen = 0, solution_draws_seen = 0;
    double last_seconds = 0;
    while (!(frame = worker.takeFinished())) {
        if (const std::optional<RunningRender> r = worker.running()) {
            EXPECT_GE(r->seconds, last_seconds);
            last_seconds = r->seconds;
            EXPECT_LE(r->progress.drawsStarted, 2u);
            uint32_t& seen = r->solution ? solution_draws_seen : frame_draws_seen;
            seen = std::max(seen, r->progress.drawsStarted);
        }
        std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
    EXPECT_EQ(frame->id, id);
    EXPECT_TRUE(frame->error.empty()) << frame->error;
    EXPECT_EQ(frame->drawCount, 2u);
    EXPECT_EQ(frame->solutionDrawCount, 2u);
    EXPECT_GE(frame_draws_seen, 1u) << "the frame's draws were never seen running";
    EXPECT_GE(solution_draws_seen, 1u) << "the solution's draws were never seen running";
}

// ---- The overlay's text layout -------------------------------------------------------------------------

// One column a character: wrapping to "columns".
int columns(std::string_view text) {
    return int(text.size());
}

std::vector<std::string> wrap(std::string_view text, int maxColumns, std::string_view indent = {}) {
    return wrapText(text, maxColumns, columns, indent);
}

using Lines = std::vector<std::string>;

TEST(WrapText, EmptyTextIsOneEmptyLine) {
    EXPECT_EQ(wrap("", 10), Lines{""});
    EXPECT_EQ(wrap("", 0), Lines{""});
    EXPECT_EQ(wrap("    ", 2), Lines{""}) << "spaces alone, too wide: nothing to show";
}

TEST(WrapText, TextThatFitsIsUnchanged) {
    EXPECT_EQ(wrap("abc def", 7), Lines{"abc def"}) << "an exact fit";
    EXPECT_EQ(wrap("  abc  def  ", 12), Lines{"  abc  def  "}) << "spaces and all";
    EXPECT_EQ(wrap("abc def", 6), (Lines{"abc", "def"})) << "one column short";
}

TEST(WrapText, BreaksAtSpacesGreedily) {
    const std::string text = "the quick brown fox jumps over the lazy dog";
    for (int width = 5; width <= int(text.size()); ++width) {
        const Lines lines = wrap(text, width);
        std::string joined;
        for (size_t i = 0; i < lines.size(); ++i) {
            EXPECT_LE(int(lines[i].size()), width) << lines[i];
            // Greedy: the next line's first word would not have fitted.
            if (i + 1 < lines.size()) {
                EXPECT_GT(lines[i].size() + 1 + std::min(lines[i + 1].find(' '), lines[i + 1].size()),
                          size_t(width))
                    << "'" << lines[i] << "' could take more at " << width;
            }
            joined += (i ? " " : "") + lines[i];
        }
        EXPECT_EQ(joined, text) << "at " << width << " columns";
    }
    EXPECT_EQ(wrap(text, 10), (Lines{"the quick", "brown fox", "jumps over", "the lazy", "dog"}));
}

TEST(WrapText, SpacesGoAtBreaksAndStayWithinLines) {
    EXPECT_EQ(wrap("a  b   c", 4), (Lines{"a  b", "c"}));
    EXPECT_EQ(wrap("  ab cd", 5), (Lines{"  ab", "cd"})) << "the first line keeps its indentation";
    EXPECT_EQ(wrap("ab cd   ", 4), (Lines{"ab", "cd"})) << "trailing spaces go";
}

TEST(WrapText, LongWordsAreBrokenBetweenCharacters) {
    EXPECT_EQ(wrap("ab abcdefghij cd", 4), (Lines{"ab", "abcd", "efgh", "ij", "cd"}));
    EXPECT_EQ(wrap("abcdefghij", 5), (Lines{"abcde", "fghij"})) << "exact multiples";
    EXPECT_EQ(wrap("abc", 0), (Lines{"a", "b", "c"})) << "at least a character a line";
    EXPECT_EQ(wrap("abc", -3), (Lines{"a", "b", "c"}));
}

TEST(WrapText, ContinuationsStartWithTheIndent) {
    EXPECT_EQ(wrap("aa bb cc dd", 5, "> "), (Lines{"aa bb", "> cc", "> dd"}));
    EXPECT_EQ(wrap("aaaaaaa", 4, "> "), (Lines{"aaaa", "> aa", "> a"})) << "counted in the width";
    EXPECT_EQ(wrap("a bbbbb", 2, ">>"), (Lines{"a", ">>b", ">>b", ">>b", ">>b", ">>b"}))
        << "an indent as wide as the line still gets a character a line";
}

TEST(WrapText, FontWidthsAddUp) {
    const std::string text = "difference from scene billboards@solution: 88829 of 230400 pixels differ";
    int sum = 0;
    for (const char c : text) sum += textWidth(std::string(1, c));
    EXPECT_EQ(textWidth(text), sum);
    EXPECT_EQ(textWidth(" "), 6);
    EXPECT_LT(textWidth("i"), textWidth("m")) << "a proportional font";
    EXPECT_EQ(textWidth("\x01\xC3\xA9"), 3 * textWidth("?")) << "bytes without a glyph count as '?'";
    const int longest_word = textWidth("billboards@solution:");
    for (const int width : {longest_word, longest_word + 37, 200, 333}) {
        const Lines lines = wrapText(text, width, textWidth);
        std::string joined;
        for (size_t i = 0; i < lines.size(); ++i) {
            EXPECT_LE(textWidth(lines[i]), width) << lines[i];
            joined += (i ? " " : "") + lines[i];
        }
        EXPECT_EQ(joined, text) << "at " << width << " font pixels";
    }
}

TEST(FitPanel, WrapsLinesToTheWidthAndKeepsColumns) {
    TextPanel panel;
    panel.lines = {"a status line that is long enough to need at least one break at this width",
                   "K\tthe solution's image, a description long enough to wrap in its column", "J\tshort",
                   "two\nlines"};
    for (const int scale : {1, 2}) {
        const int width = 260 * scale;
        const TextPanel fitted = fitPanel(panel, width, 10000, scale);
        EXPECT_LE(panelSize(fitted, scale).x, width) << "scale " << scale;
        EXPECT_GT(panelSize(panel, scale).x, width) << "the test needs a panel too wide";
        // The long line continues indented; the description continues in its column.
        ASSERT_GE(fitted.lines.size(), 7u);
        EXPECT_TRUE(fitted.lines[1].starts_with(kContinuationIndent)) << fitted.lines[1];
        size_t k = 0;
        while (k < fitted.lines.size() && !fitted.lines[k].starts_with("K\t")) ++k;
        ASSERT_LT(k + 1, fitted.lines.size());
        EXPECT_TRUE(fitted.lines[k + 1].starts_with("\t")) << fitted.lines[k + 1];
        EXPECT_EQ(fitted.lines[fitted.lines.size() - 2], "two") << "'\\n' breaks a line";
        EXPECT_EQ(fitted.lines.back(), "lines");
    }
}

TEST(FitPanel, TooManyLinesEndInANoteOfHowManyMore) {
    TextPanel panel;
    for (int i = 0; i < 30; ++i) panel.lines.push_back("line " + std::to_string(i));
    // Room for 10 lines at scale 1: padding top and bottom, 12 font pixels a line.
    const int height = 2 * kPanelPadding + 10 * kPanelLineHeight;
    const TextPanel fitted = fitPanel(panel, 600, height, 1, ": see --help");
    ASSERT_EQ(fitted.lines.size(), 10u);
    EXPECT_EQ(fitted.lines[8], "line 8");
    EXPECT_EQ(fitted.lines[9], "... 21 more lines: see --help");
    EXPECT_LE(panelSize(fitted, 1).y, height);
    EXPECT_EQ(fitPanel(panel, 600, 2 * height, 2, "").lines.size(), 10u) << "the same room at scale 2";
    EXPECT_EQ(fitPanel(panel, 600, 10000, 1).lines, panel.lines) << "room for all";
}

// ---- Scripts and options ---------------------------------------------------------------------------------

TEST(ViewerScript, ParsesKeysAndPointerTokens) {
    const std::vector<Action> a = parseScript(
        "  N p ] [ 0 d S f12 H F1 I r Esc q w shift+S Shift+Q PageUp "
        "click:160,90 drag:10,20,30,5 wheel:-2 resize:200x100 wait ");
    ASSERT_EQ(a.size(), 23u);
    EXPECT_EQ(a[0].verb, Verb::NextDraw);
    EXPECT_EQ(a[1].verb, Verb::PreviousDraw);
    EXPECT_EQ(a[2].verb, Verb::NextPrimitive);
    EXPECT_EQ(a[3].verb, Verb::PreviousPrimitive);
    EXPECT_EQ(a[4].verb, Verb::WholeFrame);
    EXPECT_EQ(a[5].verb, Verb::ToggleDepth);
    EXPECT_EQ(a[6].verb, Verb::Screenshot);
    EXPECT_EQ(a[7].verb, Verb::Screenshot);
    EXPECT_EQ(a[12].verb, Verb::Quit);
    EXPECT_EQ(a[13].verb, Verb::Quit);
    EXPECT_EQ(a[14].verb, Verb::Fly);
    EXPECT_EQ(a[14].x, 1);
    EXPECT_EQ(a[15].x, -1) << "Shift+S flies backwards";
    EXPECT_EQ(a[16].z, -1) << "Shift+Q flies down";
    EXPECT_EQ(a[17].z, 1);
    EXPECT_EQ(a[18].verb, Verb::Click);
    EXPECT_EQ(a[18].x, 160);
    EXPECT_EQ(a[18].y, 90);
    EXPECT_EQ(a[19].verb, Verb::Orbit);
    EXPECT_EQ(a[19].x, 20);
    EXPECT_EQ(a[19].y, -15);
    EXPECT_EQ(a[20].verb, Verb::Zoom);
    EXPECT_EQ(a[20].x, -2);
    EXPECT_EQ(a[21].verb, Verb::Resize);
    EXPECT_EQ(a[21].x, 200);
    EXPECT_EQ(a[21].y, 100);
    EXPECT_EQ(a[22].verb, Verb::Wait);
    EXPECT_TRUE(parseScript("").empty());
    const std::vector<Action> views = parseScript("O x L g V c K j");
    ASSERT_EQ(views.size(), 8u);
    EXPECT_EQ(views[0].verb, Verb::ToggleOverdraw);
    EXPECT_EQ(views[1].verb, Verb::ToggleNonFinite);
    EXPECT_EQ(views[2].verb, Verb::ToggleWireframe);
    EXPECT_EQ(views[3].verb, Verb::ToggleGsOutput);
    EXPECT_EQ(views[4].verb, Verb::NextStage);
    EXPECT_EQ(views[5].verb, Verb::ClosePixel);
    EXPECT_EQ(views[6].verb, Verb::ToggleSolution);
    EXPECT_EQ(views[7].verb, Verb::ToggleDifference);
    // Every key the help lists is bound, and no two bindings share a name.
    for (const char* key : {"o", "x", "l", "g", "v", "c", "k", "j"}) {
        bool listed = false;
        for (const std::string& line : keyHelp())
            listed = listed || line.starts_with(std::string(1, char(std::toupper(key[0]))) + " ");
        EXPECT_TRUE(listed) << key << " is missing from the help";
    }
}

TEST(ViewerScript, TimeKeys) {
    const std::vector<Action> a = parseScript("space . , home + = - Space");
    ASSERT_EQ(a.size(), 8u);
    EXPECT_EQ(a[0].verb, Verb::TogglePlay);
    EXPECT_EQ(a[1].verb, Verb::StepFrame);
    EXPECT_EQ(a[1].x, 1);
    EXPECT_EQ(a[2].x, -1) << ", steps back";
    EXPECT_EQ(a[3].verb, Verb::RestartTime);
    EXPECT_EQ(a[4].verb, Verb::Faster);
    EXPECT_EQ(a[5].verb, Verb::Faster) << "= is + without Shift";
    EXPECT_EQ(a[6].verb, Verb::Slower);
    EXPECT_EQ(a[7].verb, Verb::TogglePlay);
    for (const char* key : {"Space", ". / ,", "+ / -", "Home"}) {
        bool listed = false;
        for (const std::string& line : keyHelp()) listed = listed || line.starts_with(key);
        EXPECT_TRUE(listed) << key << " is missing from the help";
    }
}

// ---- The playback clock -------------------------------------------------------------------------------

TEST(Playback, StepsPauseAndStayWithinTheClocksRange) {
    Playback p;
    EXPECT_FALSE(p.step(1)) << "nothing moves before the scene is known";
    p.setScene(true, 3.0);
    EXPECT_FALSE(p.setPlaying(true)) << "starting play does not move the clock";
    EXPECT_TRUE(p.playing());
    EXPECT_TRUE(p.step(2));
    EXPECT_FALSE(p.playing()) << "a step pauses";
    EXPECT_DOUBLE_EQ(p.time(), 3.0 + 2 * kFrameStep);
    EXPECT_TRUE(p.step(-1));
    EXPECT_DOUBLE_EQ(p.time(), 3.0 + kFrameStep);
    EXPECT_TRUE(p.restart());
    EXPECT_EQ(p.time(), 3.0) << "Home is the start exactly";
    EXPECT_FALSE(p.restart()) << "already there";
    EXPECT_TRUE(p.step(-1000));
    EXPECT_EQ(p.time(), 0.0) << "never before 0";
    EXPECT_FALSE(p.step(-1));
    p.step(int(kMaxStartTime / kFrameStep) + 100);
    EXPECT_EQ(p.time(), kMaxStartTime) << "never after the latest start time";
}

TEST(Playback, PlayAdvancesByRealTimeTimesSpeedCapped) {
    Playback p;
    p.setScene(true, 1.0);
    EXPECT_FALSE(p.tick(0.05)) << "paused: no move";
    p.setPlaying(true);
    EXPECT_TRUE(p.tick(0.05));
    EXPECT_DOUBLE_EQ(p.time(), 1.05);
    p.faster();
    EXPECT_EQ(p.speed(), 2.0);
    EXPECT_TRUE(p.tick(0.05));
    EXPECT_DOUBLE_EQ(p.time(), 1.15);
    EXPECT_TRUE(p.tick(5.0)) << "a slow frame";
    EXPECT_DOUBLE_EQ(p.time(), 1.15 + kMaxPlayStep * 2) << "advances at most kMaxPlayStep of real time";
    EXPECT_FALSE(p.tick(-1.0));
    EXPECT_FALSE(p.tick(std::nan("")));
    for (int i = 0; i < 10; ++i) p.slower();
    EXPECT_EQ(p.speed(), kMinSpeed);
    for (int i = 0; i < 20; ++i) p.faster();
    EXPECT_EQ(p.speed(), kMaxSpeed);
    EXPECT_NE(p.label().find("playing x16"), std::string::npos) << p.label();
    p.setPlaying(false);
    for (int i = 0; i < 6; ++i) p.slower();
    EXPECT_NE(p.label().find("paused x1/4"), std::string::npos) << p.label();
    p.step(int(kMaxStartTime / kFrameStep));
    p.setPlaying(true);
    p.tick(0.1);
    EXPECT_EQ(p.time(), kMaxStartTime);
    EXPECT_FALSE(p.playing()) << "play stops at the latest start time";
}

TEST(Playback, StaticScenesKeepTimeZero) {
    Playback p;
    p.setScene(false, 0.0);
    p.setPlaying(true);
    EXPECT_FALSE(p.playing());
    EXPECT_FALSE(p.step(1));
    EXPECT_FALSE(p.tick(0.05));
    EXPECT_EQ(p.time(), 0.0);
    EXPECT_EQ(p.label(), "");
}

TEST(ViewerScript, ErrorsNameTheToken) {
    expectInvalidArgument([] { parseScript("N N Z S"); }, {"unknown key 'Z'"});
    expectInvalidArgument([] { parseScript("click:1"); }, {"'click:1'", "click:X,Y"});
    expectInvalidArgument([] { parseScript("click:1,2,3"); }, {"'click:1,2,3'"});
    expectInvalidArgument([] { parseScript("click:-1,2"); }, {"'click:-1,2'"});
    expectInvalidArgument([] { parseScript("click:a,b"); }, {"'click:a,b'"});
    expectInvalidArgument([] { parseScript("drag:1,2,3"); }, {"'drag:1,2,3'"});
    expectInvalidArgument([] { parseScript("wheel:"); }, {"'wheel:'"});
    expectInvalidArgument([] { parseScript("resize:0x10"); }, {"'resize:0x10'"});
    expectInvalidArgument([] { parseScript("Ctrl+N"); }, {"'Ctrl+N'"});
}

// Parses `raster view <args>` as build/bin/raster does, then runs it.
int runView(std::vector<std::string> args) {
    CLI::App app("raster", "raster");
    const Command view = addView(app);
    args.insert(args.begin(), {"raster", "view"});
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    app.parse(int(argv.size()), argv.data());
    return view.run();
}

// The command line `raster view <args>` does not parse, and says why with each of `parts`.
void expectUsageError(std::vector<std::string> args, std::initializer_list<std::string> parts) {
    try {
        runView(args);
        ADD_FAILURE() << "expected CLI::ParseError, nothing was thrown";
    } catch (const CLI::ParseError& e) {
        const std::string message = e.what();
        for (const std::string& part : parts)
            EXPECT_NE(message.find(part), std::string::npos)
                << "message \"" << message << "\" lacks \"" << part << "\"";
    }
}

TEST(ViewerCommand, BadOptionsNameTheCulprit) {
    // All of these fail before SDL starts.
    expectUsageError({"smog", "--headless"}, {"scene: smog not in", "particles"});
    expectUsageError({}, {"scene is required"});
    expectUsageError({"particles", "--size", "0x10"},
                     {"--size: W of '0x10'", "Value 0 not in range 1 to 16384"});
    expectUsageError({"particles", "--size", "320"}, {"--size", "'320'"});
    expectUsageError({"particles", "--size", "320x"}, {"--size: H of '320x'"});
    expectUsageError({"particles", "--count", "50000001"}, {"--count", "50000001"});
    expectUsageError({"particles", "--threads", "0"}, {"--threads", "Value 0"});
    expectUsageError({"particles", "--bogus"}, {"--bogus"});
    expectUsageError({"particles", "--script"}, {"--script", "required"});
    expectUsageError({"particles", "--headless", "--script", "N ] Z"}, {"--script", "'Z'"});
    expectUsageError({"fog", "--fog", "thick"}, {"--fog", "thick"});
    expectUsageError({"fog", "--screenshot-dir", ""}, {"--screenshot-dir"});
    expectUsageError({"particles", "--headless", "--solution", "smog"},
                     {"unknown --solution 'smog'", "reference", "particles, fog", ".png"});
    expectUsageError({"particles", "--solution", "lab.jpg"}, {"'lab.jpg'"});
    expectUsageError({"particles", "--solution", ""}, {"--solution: takes"});
    expectUsageError({"particles", "--solution"}, {"--solution", "required"});
    // raster render --view opens the viewer without a command line: the same names are refused.
    ViewerOptions bad_scene, bad_solution;
    bad_scene.scene = "smog";
    bad_solution.solution = "smog";
    expectInvalidArgument([&] { openViewer(bad_scene); }, {"unknown scene 'smog'"});
    expectInvalidArgument([&] { openViewer(bad_solution); }, {"unknown --solution 'smog'"});
}

TEST(SceneCamera, DefaultIsTheScenesOwnAndBadOnesAreRefused) {
    for (const std::string& name : sceneNames()) {
        // (60: a count every scene takes; sprite-methods draws at most 64 targets a row.)
        SceneOptions plain{.width = 64, .height = 36, .count = 60, .cubes = 2};
        SceneOptions explicit_camera = plain;
        explicit_camera.camera = defaultCamera(name);
        Context ctx;
        RenderTarget a(64, 36), b(64, 36);
        DepthTarget da(64, 36), db(64, 36);
        makeScene(name, plain)->render(ctx, a, da);
        makeScene(name, explicit_camera)->render(ctx, b, db);
        EXPECT_TRUE(a == b) << name;
        EXPECT_TRUE(da == db) << name;
    }
    expectInvalidArgument([] { defaultCamera("smog"); }, {"'smog'"});
    SceneOptions bad{.width = 8, .height = 8};
    bad.camera = SceneCamera{{1, 2, 3}, {1, 2, 3}};
    expectInvalidArgument([&] { makeScene("particles", bad); }, {"camera eye (1.0", "target (1.0"});
    bad.camera = SceneCamera{{0, 5, 0}, {0, 0, 0}};
    expectInvalidArgument([&] { makeScene("fog", bad); }, {"one above the other"});
}

// ---- The viewer, headless ------------------------------------------------------------------------------

class ViewerTest : public ::testing::Test {
  protected:
    void SetUp() override {
        const std::string name = ::testing::UnitTest::GetInstance()->current_test_info()->name();
        dir_ = std::filesystem::temp_directory_path() /
               ("raster_viewer_test_" + name + "_" + std::to_string(getpid()));
        std::filesystem::remove_all(dir_);
    }
    void TearDown() override { std::filesystem::remove_all(dir_); }

    ViewerOptions options(const std::string& script, const std::string& scene = "particles") const {
        ViewerOptions o;
        o.solution = solution_;
        o.scene = scene;
        o.sceneOptions = {.width = kWidth, .height = kHeight, .count = kParticles, .cubes = 4};
        o.headless = true;
        o.script = parseScript(script);
        o.screenshotDir = dir_.string();
        return o;
    }

    // Runs the script headless; returns the viewer's screenshots, decoded.
    std::vector<ImageRgba8> run(const std::string& script, const std::string& scene = "particles") {
        Viewer viewer(options(script, scene));
        viewer.run();
        last_messages_ = viewer.messages();
        if (viewer.shownFrame()) last_log_ = viewer.shownFrame()->drawLog;
        last_traced_ = viewer.shownFrame() && viewer.shownFrame()->trace;
        last_solved_ = viewer.shownFrame() && viewer.shownFrame()->solution;
        last_notes_ = viewer.viewNotes();
        last_camera_ = viewer.camera();
        last_playback_ = viewer.playback();
        last_frame_time_ = viewer.shownFrame() ? viewer.shownFrame()->sceneTime : -1;
        std::vector<ImageRgba8> shots;
        for (const std::string& path : viewer.screenshots()) shots.push_back(readImageRgba8(path));
        last_paths_ = viewer.screenshots();
        return shots;
    }

    // The scene rendered straight through the library.
    static RenderTarget direct(const Context::StepLimit& limit, const std::string& scene = "particles",
                               std::optional<SceneCamera> camera = std::nullopt, uint32_t width = kWidth,
                               uint32_t height = kHeight, const ContextOptions& context = {}) {
        SceneOptions o{.width = width, .height = height, .count = kParticles, .cubes = 4};
        o.camera = camera;
        Context ctx(context);
        ctx.setStepLimit(limit);
        RenderTarget color(width, height);
        DepthTarget depth(width, height);
        makeScene(scene, o)->render(ctx, color, depth);
        return color;
    }

    static void expectSameImage(const ImageRgba8& shot, const RenderTarget& expected,
                                const std::string& what) {
        ASSERT_EQ(shot.width, expected.width()) << what;
        ASSERT_EQ(shot.height, expected.height()) << what;
        EXPECT_TRUE(shot.pixels == expected.toRgba8()) << what << ": the screenshot is not the framebuffer";
    }

    std::filesystem::path dir_;
    std::vector<std::string> last_messages_, last_paths_;
    std::vector<PipelineStatistics> last_log_;
    SceneCamera last_camera_{};
    Playback last_playback_;
    double last_frame_time_ = -1;  // the shown frame's scene time
    std::vector<std::string> last_notes_;
    bool last_traced_ = false;
    std::string solution_;      // --solution of the next run
    bool last_solved_ = false;  // the last frame shown came with a rendered solution
};

std::vector<char> fileBytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST_F(ViewerTest, WholeFrameScreenshotIsTheFramebuffer) {
    for (const std::string scene : {"particles", "fog"}) {
        const std::vector<ImageRgba8> shots = run("0 S", scene);
        ASSERT_EQ(shots.size(), 1u) << scene;
        const RenderTarget expected = direct({}, scene);
        expectSameImage(shots[0], expected, scene);
        // Byte for byte the file RenderTarget::savePng writes: no overlay, no conversion.
        const std::string reference = (dir_ / (scene + "-direct.png")).string();
        expected.savePng(reference);
        EXPECT_EQ(fileBytes(last_paths_[0]), fileBytes(reference)) << scene;
        EXPECT_NE(last_paths_[0].find(scene + "-0001.png"), std::string::npos) << last_paths_[0];
    }
}

// The fire after `steps` frames of 1/60 s from its start, as `raster render fire --frames --fps 60`
// draws them.
RenderTarget fireAfter(int steps) {
    SceneOptions o{.width = kWidth, .height = kHeight, .count = kParticles};
    std::unique_ptr<Scene> scene = makeScene("fire", o);
    for (int i = 0; i < steps; ++i) scene->advance(kFrameStep);
    Context ctx;
    RenderTarget color(kWidth, kHeight);
    DepthTarget depth(kWidth, kHeight);
    scene->render(ctx, color, depth);
    return color;
}

TEST_F(ViewerTest, FrameStepsAreTheFramesOfTheClock) {
    // Headless starts paused: the first frame is the start, then . forward, , back (a rebuilt
    // scene), Home the start again: each the same bits as the scene advanced that many frames.
    const std::vector<ImageRgba8> shots = run("S . . . S , S home S", "fire");
    ASSERT_EQ(shots.size(), 4u);
    const RenderTarget start = fireAfter(0);
    expectSameImage(shots[0], start, "the start");
    expectSameImage(shots[1], fireAfter(3), ". . .");
    expectSameImage(shots[2], fireAfter(2), ". . . ,");
    expectSameImage(shots[3], start, "Home");
    EXPECT_FALSE(shots[0].pixels == shots[1].pixels) << "the fire moved in three frames";
    EXPECT_TRUE(last_playback_.animated());
    EXPECT_FALSE(last_playback_.playing()) << "headless never plays on its own";
    EXPECT_EQ(last_frame_time_, kDefaultFireTime);
}

TEST_F(ViewerTest, PlayMovesTheClockAndStepsPauseIt) {
    run("space wait . S", "fire");
    EXPECT_FALSE(last_playback_.playing()) << ". pauses";
    EXPECT_GT(last_playback_.time(), kDefaultFireTime + kFrameStep) << "play moved the clock";
    EXPECT_NEAR(last_frame_time_, last_playback_.time(), 1e-9) << "the frame shown is of the clock's time";
    ASSERT_FALSE(last_paths_.empty());
    bool timed = false;
    for (const std::string& m : last_messages_)
        timed =
            timed || (m.find(last_paths_[0]) != std::string::npos && m.find(", t 3.0") != std::string::npos);
    EXPECT_TRUE(timed) << "a screenshot of an animated scene says its time";
    bool said = false;
    run("+ + -", "fire");
    for (const std::string& m : last_messages_) said = said || m.find("paused x2") != std::string::npos;
    EXPECT_TRUE(said) << "speed changes are said";
    EXPECT_EQ(last_playback_.speed(), 2.0);
}

TEST_F(ViewerTest, TimeKeysOnAStaticSceneSaySoOnce) {
    const std::vector<ImageRgba8> shots = run(". space , S", "particles");
    ASSERT_EQ(shots.size(), 1u);
    expectSameImage(shots[0], direct({}), "a static scene ignores time");
    int said = 0;
    for (const std::string& m : last_messages_) said += m.find("is static") != std::string::npos;
    EXPECT_EQ(said, 1);
    EXPECT_FALSE(last_playback_.animated());
}

TEST_F(ViewerTest, ScreenshotsAreNumberedWithoutOverwriting) {
    run("S S");
    ASSERT_EQ(last_paths_.size(), 2u);
    EXPECT_EQ(std::filesystem::path(last_paths_[0]).filename(), "particles-0001.png");
    EXPECT_EQ(std::filesystem::path(last_paths_[1]).filename(), "particles-0002.png");
    run("S");
    ASSERT_EQ(last_paths_.size(), 1u);
    EXPECT_EQ(std::filesystem::path(last_paths_[0]).filename(), "particles-0003.png")
        << "an earlier run's shots stay";
    bool printed = false;
    for (const std::string& m : last_messages_)
        printed = printed || m.find("screenshot " + last_paths_[0]) == 0;
    EXPECT_TRUE(printed) << "the path is printed";
}

TEST_F(ViewerTest, NextDrawIsStepLimitOne) {
    const std::vector<ImageRgba8> shots = run("N S");
    ASSERT_EQ(shots.size(), 1u);
    expectSameImage(shots[0], direct({1}), "N");
    EXPECT_FALSE(shots[0].pixels == direct({}).toRgba8()) << "draw 1 alone must differ from the whole frame";
    ASSERT_EQ(last_log_.size(), 2u) << "the log has an entry per draw, skipped ones too";
    EXPECT_GT(last_log_[0].psInvocations, 0u) << "the occluder ran";
    EXPECT_EQ(last_log_[1], PipelineStatistics{}) << "the particles were skipped";
}

TEST_F(ViewerTest, ForwardTwiceBackOnceIsForwardOnce) {
    const std::vector<ImageRgba8> shots = run("N N P S N S P S");
    ASSERT_EQ(shots.size(), 3u);
    const RenderTarget one = direct({1});
    expectSameImage(shots[0], one, "N N P");
    expectSameImage(shots[1], direct({2}), "N N P N");
    expectSameImage(shots[2], one, "N N P N P");
    const std::vector<ImageRgba8> fog = run("N N P S", "fog");
    ASSERT_EQ(fog.size(), 1u);
    expectSameImage(fog[0], direct({1}, "fog"), "fog N N P");
}

TEST_F(ViewerTest, PrimitiveStepsWithinADraw) {
    // Forwards to the 40th particle and back to the 30th must be the 30th reached forwards.
    std::string forward = "N", back;
    for (int i = 0; i < 40; ++i) forward += " ]";
    for (int i = 0; i < 10; ++i) back += " [";
    const std::vector<ImageRgba8> a = run(forward + back + " S");
    const std::vector<PipelineStatistics> log_a = last_log_;
    std::string thirty = "N";
    for (int i = 0; i < 30; ++i) thirty += " ]";
    const std::vector<ImageRgba8> b = run(thirty + " S");
    ASSERT_EQ(a.size(), 1u);
    ASSERT_EQ(b.size(), 1u);
    const RenderTarget expected = direct({2, 30});
    expectSameImage(a[0], expected, "N, 40 ], 10 [");
    expectSameImage(b[0], expected, "N, 30 ]");
    EXPECT_FALSE(expected == direct({2, 29})) << "one particle more must show";
    // The statistics are those of the shown step: 30 particles of the second draw went through the GS.
    ASSERT_EQ(log_a.size(), 2u);
    EXPECT_EQ(log_a[1].gsInvocations, 30u);
    EXPECT_EQ(log_a[1].gsPrimitives, 60u);
    EXPECT_EQ(log_a[1].iaPrimitives, kParticles) << "the draw's input, whatever the limit";
    EXPECT_TRUE(log_a == last_log_);
    run("N ] ]");
    ASSERT_EQ(last_log_.size(), 2u);
    EXPECT_EQ(last_log_[1].gsInvocations, 2u);
    // "]" from the end of draw 1 is the first particle; "[" from the whole frame is all but the last.
    const std::vector<ImageRgba8> c = run("N ] S 0 [ S");
    ASSERT_EQ(c.size(), 2u);
    expectSameImage(c[0], direct({2, 1}), "N ]");
    expectSameImage(c[1], direct({2, kParticles - 1}), "0 [");
}

TEST_F(ViewerTest, ClickPrintsColourAndDepth) {
    run("N click:160,90 ] ] click:160,90 click:5,5 click:400,10");
    const auto line = [&](const Context::StepLimit& limit, uint32_t x, uint32_t y) {
        Context ctx;
        ctx.setStepLimit(limit);
        RenderTarget color(kWidth, kHeight);
        DepthTarget depth(kWidth, kHeight);
        makeScene("particles", {.width = kWidth, .height = kHeight, .count = kParticles})
            ->render(ctx, color, depth);
        const uint8_t* p = color.rgba8() + 4 * (size_t(y) * kWidth + x);
        char text[160];
        std::snprintf(text, sizeof text, "pixel %u,%u: rgba %d %d %d %d, depth %.7g", x, y, p[0], p[1], p[2],
                      p[3], double(depth.load(x, y)));
        return std::string(text);
    };
    std::vector<std::string> clicks;
    for (const std::string& m : last_messages_)
        if ((m.starts_with("pixel ") && !m.starts_with("pixel (")) || m.starts_with("click "))
            clicks.push_back(m);
    ASSERT_EQ(clicks.size(), 4u);
    EXPECT_EQ(clicks[0], line({1}, 160, 90));
    EXPECT_NE(clicks[0].find("rgba 89 140 64 255"), std::string::npos) << "the occluder: " << clicks[0];
    EXPECT_EQ(clicks[1], line({2, 2}, 160, 90));
    EXPECT_NE(clicks[0], clicks[1]) << "particle 0 sits in front of the occluder's centre";
    EXPECT_EQ(clicks[2], line({2, 2}, 5, 5));
    EXPECT_EQ(clicks[3], "click 400,10: outside the framebuffer");
}

TEST_F(ViewerTest, DepthViewShowsDepthAsGrey) {
    const std::vector<ImageRgba8> shots = run("D S D S");
    ASSERT_EQ(shots.size(), 2u);
    expectSameImage(shots[1], direct({}), "D D");
    const auto grey = [&](uint32_t x, uint32_t y) {
        const uint8_t* p = &shots[0].pixels[4 * (size_t(y) * kWidth + x)];
        EXPECT_EQ(p[0], p[1]);
        EXPECT_EQ(p[0], p[2]);
        return int(p[0]);
    };
    EXPECT_EQ(grey(2, 2), 255) << "cleared depth is white";
    EXPECT_LE(grey(160, 90), 224) << "the occluder is drawn depth, darker than the clear";
    // The occluder leans away from the eye above it: its top is nearer, so darker, than its bottom.
    EXPECT_LT(grey(160, 80), grey(160, 130));
}

TEST_F(ViewerTest, CameraOrbitsZoomsFliesAndResets) {
    const SceneCamera start = defaultCamera("particles");
    const std::vector<ImageRgba8> shots = run("drag:100,90,140,80 S wheel:2 S R S w shift+D e S");
    ASSERT_EQ(shots.size(), 4u);
    const SceneCamera orbited = orbit(start, 40, -10);
    expectSameImage(shots[0], direct({}, "particles", orbited), "after the drag");
    expectSameImage(shots[1], direct({}, "particles", zoom(orbited, 2)), "after the wheel");
    expectSameImage(shots[2], direct({}), "R resets to the scene's own camera");
    const SceneCamera flown = fly(fly(fly(start, 1, 0, 0), 0, 1, 0), 0, 0, 1);
    expectSameImage(shots[3], direct({}, "particles", flown), "after flying");
    EXPECT_EQ(last_camera_.eye, flown.eye);
    EXPECT_EQ(last_camera_.target, flown.target);
    EXPECT_FALSE(shots[0].pixels == shots[2].pixels);
}

// ---- The trace views ---------------------------------------------------------------------------------

// The scene traced straight through the library.
struct DirectTrace {
    RenderTarget color;
    DepthTarget depth;
    std::unique_ptr<Trace> trace;
    Viewport viewport;
};
DirectTrace traced(const Context::StepLimit& limit, const TraceOptions& options,
                   const std::string& scene = "particles") {
    DirectTrace t{
        RenderTarget(kWidth, kHeight), DepthTarget(kWidth, kHeight), std::make_unique<Trace>(options), {}};
    Context ctx;
    ctx.setStepLimit(limit);
    ctx.setTrace(t.trace.get());
    makeScene(scene, {.width = kWidth, .height = kHeight, .count = kParticles, .cubes = 4})
        ->render(ctx, t.color, t.depth);
    t.viewport = ctx.viewport();
    return t;
}

std::vector<std::string> lines(const std::string& text) {
    std::vector<std::string> out;
    size_t start = 0;
    while (start < text.size()) {
        const size_t end = std::min(text.find('\n', start), text.size());
        out.push_back(text.substr(start, end - start));
        start = end + 1;
    }
    return out;
}

double distanceToSegment(glm::dvec2 p, glm::dvec2 a, glm::dvec2 b) {
    const glm::dvec2 d = b - a;
    const double len2 = glm::dot(d, d);
    const double t = len2 > 0 ? std::clamp(glm::dot(p - a, d) / len2, 0.0, 1.0) : 0.0;
    return glm::length(p - (a + t * d));
}

// Pixel centres within `reach` of one of the segments.
bool nearSegments(uint32_t x, uint32_t y, const std::vector<std::pair<glm::dvec2, glm::dvec2>>& segments,
                  double reach) {
    for (const auto& [a, b] : segments)
        if (distanceToSegment({x + 0.5, y + 0.5}, a, b) <= reach) return true;
    return false;
}

TEST(TraceViews, HeatRampIsWhiteOnlyAtTheMaximum) {
    EXPECT_EQ(heatColour(0, 5), (Rgb{0, 0, 0}));
    EXPECT_EQ(heatColour(5, 5), (Rgb{255, 255, 255}));
    for (const uint32_t max : {2u, 3u, 7u, 100u, 100000u})
        for (uint32_t c = 1; c < max; c += std::max(1u, max / 50)) {
            EXPECT_NE(heatColour(c, max), (Rgb{255, 255, 255})) << c << " of " << max;
            EXPECT_NE(heatColour(c, max), (Rgb{0, 0, 0})) << c << " of " << max;
        }
    EXPECT_EQ(heatColour(99999, 100000)[0], 255);
    EXPECT_LT(heatColour(99999, 100000)[2], 255);
}

TEST(TraceViews, NonFiniteImageDimsAndHighlights) {
    const std::vector<uint8_t> rgba = {255, 255, 255, 255, 30, 60, 90, 255, 255, 0, 255, 255};
    size_t highlighted = 0;
    const std::vector<uint8_t> out = nonFiniteImage(rgba, {0, 2, 0}, &highlighted);
    EXPECT_EQ(highlighted, 1u);
    EXPECT_EQ(out, (std::vector<uint8_t>{85, 85, 85, 255, 255, 0, 255, 255, 85, 0, 85, 255}))
        << "a magenta pixel of the scene, dimmed, is no longer the highlight";
}

TEST(TraceViews, LinesAreClippedToTheImage) {
    std::vector<uint8_t> rgba(4 * 10 * 10, 0);
    Canvas canvas{rgba, 10, 10};
    canvas.line({-1e9f, 5.5f}, {1e9f, 5.5f}, {1, 2, 3});  // far off both sides: clipped, not walked
    canvas.line({2.5f, 2.5f}, {2.5f, 2.5f}, {9, 9, 9});
    for (uint32_t x = 0; x < 10; ++x) EXPECT_EQ(rgba[4 * (5 * 10 + x)], 1) << x;
    EXPECT_EQ(rgba[4 * (2 * 10 + 2)], 9);
    size_t set = 0;
    for (size_t i = 3; i < rgba.size(); i += 4) set += rgba[i] != 0;
    EXPECT_EQ(set, 11u);
}

TEST_F(ViewerTest, NormalFramesAreNotTraced) {
    run("N ] S 0 D S");
    EXPECT_FALSE(last_traced_) << "no view needed a trace";
    run("O S O S");
    EXPECT_TRUE(last_traced_) << "O asked for one; switching it off keeps the frame shown";
}

TEST_F(ViewerTest, OverdrawViewIsTheTracesCounts) {
    // Overdraw of the whole frame; of draw 1 (O off and on again); then O off: colour.
    const std::vector<ImageRgba8> shots = run("O S N O O S O S");
    std::string hottest_draw1;
    ASSERT_EQ(shots.size(), 3u);
    for (const auto& [shot, limit, what] : {std::tuple{0, Context::StepLimit{}, "whole frame"},
                                            std::tuple{1, Context::StepLimit{1}, "draw 1"}}) {
        const DirectTrace direct = traced(limit, {});
        const std::vector<uint32_t>& counts = direct.trace->overdraw();
        ASSERT_EQ(counts.size(), size_t(kWidth) * kHeight);
        uint32_t max = 0;
        EXPECT_EQ(shots[size_t(shot)].pixels, overdrawImage(counts, kWidth, kHeight, &max)) << what;
        // The hottest pixels, and only they, are white; every pixel with a fragment is lit.
        size_t hottest = 0, first = 0;
        for (size_t i = 0; i < counts.size(); ++i) {
            const uint8_t* p = &shots[size_t(shot)].pixels[4 * i];
            const bool white = p[0] == 255 && p[1] == 255 && p[2] == 255;
            EXPECT_EQ(white, counts[i] == max)
                << what << " pixel " << i % kWidth << "," << i / kWidth << ": count " << counts[i] << " of "
                << max << ", shown " << int(p[0]) << " " << int(p[1]) << " " << int(p[2]);
            EXPECT_EQ(p[0] + p[1] + p[2] == 0, counts[i] == 0) << what << " pixel " << i;
            if (counts[i] == max && hottest++ == 0) first = i;
        }
        if (shot == 0) {
            EXPECT_GT(max, 3u) << "particles pile up";
        } else {
            EXPECT_EQ(max, 1u) << "the occluder alone covers each pixel once";
            hottest_draw1 = "overdraw: fragments rasterised per pixel, max 1 at " +
                            std::to_string(first % kWidth) + "," + std::to_string(first / kWidth) + " (" +
                            std::to_string(hottest) + " pixels)";
        }
    }
    expectSameImage(shots[2], direct({1}), "O O: the colour image again");
    EXPECT_TRUE(last_notes_.empty()) << "O is off";
    run("N O");
    ASSERT_EQ(last_notes_.size(), 1u);
    EXPECT_EQ(last_notes_[0], hottest_draw1) << "the HUD names the hottest pixel";
}

TEST_F(ViewerTest, NanViewOfANormalSceneHighlightsNothing) {
    for (const std::string scene : {"particles", "fog"}) {
        const std::vector<ImageRgba8> shots = run("X S X S", scene);
        ASSERT_EQ(shots.size(), 2u);
        const RenderTarget expected = direct({}, scene);
        std::vector<uint8_t> dimmed = expected.toRgba8();
        dim(dimmed);
        EXPECT_TRUE(shots[0].pixels == dimmed) << scene << ": the dimmed image, nothing highlighted";
        size_t magenta = 0;
        for (size_t i = 0; i < shots[0].pixels.size(); i += 4)
            magenta +=
                shots[0].pixels[i] == 255 && shots[0].pixels[i + 1] == 0 && shots[0].pixels[i + 2] == 255;
        EXPECT_EQ(magenta, 0u) << scene;
        expectSameImage(shots[1], expected, scene + ": X X");
        EXPECT_EQ(last_notes_.size(), 0u) << "the view is off";
    }
    run("X");
    ASSERT_EQ(last_notes_.size(), 1u);
    EXPECT_EQ(last_notes_[0], "NaN/Inf: 0 pixels with a non-finite shader output (magenta)");
}

TEST_F(ViewerTest, ClickPrintsThePixelsHistory) {
    // Stepped (the occluder and two particles) and the whole frame, the same pixel twice.
    run("N ] ] click:160,90 0 click:160,90 click:160,90 C click:5,5");
    const auto expected = [](const Context::StepLimit& limit, int32_t x, int32_t y) {
        const DirectTrace t = traced(limit, {.pixels = {x, y, x, y}, .geometry = false});
        return std::pair{t.trace->pixelHistory(x, y).size(), lines(formatPixelHistory(*t.trace, x, y))};
    };
    const std::vector<std::pair<Context::StepLimit, std::pair<int32_t, int32_t>>> clicks = {
        {{2, 2}, {160, 90}}, {{}, {160, 90}}, {{}, {160, 90}}, {{}, {5, 5}}};
    size_t m = 0;
    for (const auto& [limit, pixel] : clicks) {
        const auto [x, y] = pixel;
        const std::string head = "pixel " + std::to_string(x) + "," + std::to_string(y) + ": rgba";
        while (m < last_messages_.size() && !last_messages_[m].starts_with(head)) ++m;
        ASSERT_LT(m, last_messages_.size()) << "no click report " << head;
        const auto [count, text] = expected(limit, x, y);
        ASSERT_LE(m + 1 + text.size(), last_messages_.size());
        const std::vector<std::string> printed(last_messages_.begin() + long(m) + 1,
                                               last_messages_.begin() + long(m + 1 + text.size()));
        EXPECT_EQ(printed, text) << head << ": the printed history is formatPixelHistory's";
        EXPECT_EQ(printed[0], "pixel (" + std::to_string(x) + ", " + std::to_string(y) +
                                  "): " + std::to_string(count) + " fragment" + (count == 1 ? "" : "s"));
        if (x == 160 && limit.draws == 2) {
            EXPECT_EQ(count, 2u) << "the occluder and particle 0";
        }
        if (x == 160 && limit.draws != 2) {
            EXPECT_GT(count, 2u);
        }
        m += 1 + text.size();
    }
}

// The segments of input primitive `primitive` of `draw` after setup, from a direct trace.
std::vector<std::pair<glm::dvec2, glm::dvec2>> primitiveEdges(const TraceDraw& draw, uint32_t primitive) {
    std::vector<std::pair<glm::dvec2, glm::dvec2>> edges;
    for (const TracePrimitive& p : draw.primitives) {
        if (p.primitive != primitive) continue;
        const auto v = [&](int i) { return glm::dvec2(p.screen[i].x, p.screen[i].y); };
        if (p.vertexCount == 3) edges.insert(edges.end(), {{v(0), v(1)}, {v(1), v(2)}, {v(2), v(0)}});
        if (p.vertexCount == 4)
            edges.insert(edges.end(), {{v(0), v(1)}, {v(1), v(3)}, {v(3), v(2)}, {v(2), v(0)}});
    }
    return edges;
}

TEST_F(ViewerTest, WireframeOfTheCurrentPrimitiveIsNearItsEdges) {
    // The third primitive: of the particles' second draw (billboards), of the fog's first (triangles).
    struct Case {
        std::string scene, steps;
        Context::StepLimit limit, next;
        uint32_t draw;
    };
    for (const Case& c :
         {Case{"particles", "N ] ] ]", {2, 3}, {2, 4}, 1}, Case{"fog", "] ] ]", {1, 3}, {1, 4}, 0}}) {
        const std::vector<ImageRgba8> shots = run(c.steps + " S L S ] L S", c.scene);
        ASSERT_EQ(shots.size(), 3u) << c.scene;
        expectSameImage(shots[0], direct(c.limit, c.scene), c.scene + " before L");
        expectSameImage(shots[2], direct(c.next, c.scene), c.scene + " after L L");
        const DirectTrace t = traced(c.limit, {}, c.scene);
        const TraceDraw* draw = findTraceDraw(*t.trace, c.draw);
        ASSERT_NE(draw, nullptr);
        const auto edges = primitiveEdges(*draw, 2);
        ASSERT_FALSE(edges.empty()) << c.scene << ": primitive 2 was set up";
        size_t changed = 0;
        for (uint32_t y = 0; y < kHeight; ++y)
            for (uint32_t x = 0; x < kWidth; ++x) {
                const size_t i = 4 * (size_t(y) * kWidth + x);
                if (std::equal(&shots[0].pixels[i], &shots[0].pixels[i] + 4, &shots[1].pixels[i])) continue;
                ++changed;
                EXPECT_TRUE(nearSegments(x, y, edges, 1.0)) << c.scene << ": pixel " << x << "," << y;
                EXPECT_EQ((Rgb{shots[1].pixels[i], shots[1].pixels[i + 1], shots[1].pixels[i + 2]}),
                          kCurrentPrimitiveColour);
            }
        EXPECT_GE(changed, 8u) << c.scene;
    }
    run("N ] ] ] L");
    ASSERT_EQ(last_notes_.size(), 1u);
    EXPECT_EQ(last_notes_[0], "primitive 3 of draw 2 (SV_PrimitiveID 2): rectangle (yellow)");
    run("L");
    ASSERT_EQ(last_notes_.size(), 1u);
    EXPECT_EQ(last_notes_[0], "wireframe: step with ] to a primitive");
}

TEST_F(ViewerTest, GeometryShaderOutputAndStages) {
    // G, then V through every stage: VS output, GS output (G's picture), set-up primitives, final.
    const std::vector<ImageRgba8> shots = run("N ] ] ] G S G V S V S V S V S");
    ASSERT_EQ(shots.size(), 5u);
    const Context::StepLimit limit{2, 3};
    const DirectTrace t = traced(limit, {});
    const TraceDraw* draw = findTraceDraw(*t.trace, 1);
    ASSERT_NE(draw, nullptr);
    ASSERT_EQ(draw->gsVertices.size(), 12u) << "three billboards, a 4-vertex strip each";
    // The stage views stop the current draw at their stage: under the overlay, the framebuffer
    // before draw 2's pixels (the occluder alone).
    const DirectTrace staged = traced({2, 3, Context::Stage::Setup}, {});
    EXPECT_TRUE(staged.color == traced({1}, {}).color);
    EXPECT_FALSE(staged.color == t.color);
    std::vector<uint8_t> dimmed = staged.color.toRgba8();
    dim(dimmed);
    // The GS output's edges: each strip's (i, i+1) and (i, i+2), in screen space.
    std::vector<std::pair<glm::dvec2, glm::dvec2>> gs_edges;
    std::vector<glm::dvec2> centres;
    for (size_t s = 0; s < 12; s += 4) {
        glm::dvec2 v[4], centre{0.0};
        for (int i = 0; i < 4; ++i) {
            const std::vector<float>& val = draw->gsVertices[s + size_t(i)].values;
            const size_t p = draw->gsPosition;
            glm::vec2 screen;
            ASSERT_TRUE(clipToScreen({val[p], val[p + 1], val[p + 2], val[p + 3]}, t.viewport, screen));
            v[i] = screen, centre += v[i] / 4.0;
        }
        gs_edges.insert(gs_edges.end(),
                        {{v[0], v[1]}, {v[1], v[2]}, {v[2], v[3]}, {v[0], v[2]}, {v[1], v[3]}});
        centres.push_back(centre);
    }
    const auto check = [&](const ImageRgba8& shot, const Rgb& colour, const auto& near, const char* what) {
        size_t drawn = 0;
        for (uint32_t y = 0; y < kHeight; ++y)
            for (uint32_t x = 0; x < kWidth; ++x) {
                const size_t i = 4 * (size_t(y) * kWidth + x);
                if (std::equal(&shot.pixels[i], &shot.pixels[i] + 4, &dimmed[i])) continue;
                ++drawn;
                EXPECT_TRUE(near(x, y)) << what << ": pixel " << x << "," << y;
                EXPECT_EQ((Rgb{shot.pixels[i], shot.pixels[i + 1], shot.pixels[i + 2]}), colour) << what;
            }
        EXPECT_GE(drawn, 9u) << what;
    };
    check(
        shots[0], kGsColour, [&](uint32_t x, uint32_t y) { return nearSegments(x, y, gs_edges, 1.0); }, "G");
    check(
        shots[1], kVertexColour,
        [&](uint32_t x, uint32_t y) {
            for (const glm::dvec2& c : centres)
                if (std::abs(x + 0.5 - c.x) <= 2.0 && std::abs(y + 0.5 - c.y) <= 2.0) return true;
            return false;
        },
        "V: the GS invocations' centres");
    EXPECT_EQ(shots[2].pixels, shots[0].pixels) << "V's second stage is G's";
    std::vector<std::pair<glm::dvec2, glm::dvec2>> set_up;
    for (uint32_t p = 0; p < 3; ++p) {
        const auto e = primitiveEdges(*draw, p);
        set_up.insert(set_up.end(), e.begin(), e.end());
    }
    check(
        shots[3], kRasterizedColour, [&](uint32_t x, uint32_t y) { return nearSegments(x, y, set_up, 1.0); },
        "V: set-up primitives");
    expectSameImage(shots[4], direct(limit), "V back to the final image");
    // The fog scene has no geometry shader: its VS output is in clip space and placed directly.
    run("N ] ] V", "fog");
    ASSERT_EQ(last_notes_.size(), 1u);
    EXPECT_NE(last_notes_[0].find("vertices on screen"), std::string::npos) << last_notes_[0];
    run("N ] ] G", "fog");
    ASSERT_EQ(last_notes_.size(), 1u);
    EXPECT_NE(last_notes_[0].find("has no geometry shader"), std::string::npos) << last_notes_[0];
}

TEST_F(ViewerTest, ResizeRendersAtTheWindowsSize) {
    const std::vector<ImageRgba8> shots = run("N resize:200x100 S");
    ASSERT_EQ(shots.size(), 1u);
    expectSameImage(shots[0], direct({1}, "particles", std::nullopt, 200, 100), "200x100");
}

// ---- The solution views (--solution, K, J) -------------------------------------------------------------

bool allBlack(const ImageRgba8& image) {
    for (size_t i = 0; i < image.pixels.size(); i += 4)
        if (image.pixels[i] || image.pixels[i + 1] || image.pixels[i + 2] || image.pixels[i + 3] != 255)
            return false;
    return true;
}

bool said(const std::vector<std::string>& messages, const std::string& line) {
    return std::find(messages.begin(), messages.end(), line) != messages.end();
}

TEST_F(ViewerTest, SolutionOfTheSameSceneDiffersNowhere) {
    solution_ = "particles";
    const std::vector<ImageRgba8> shots = run("J S K S N J S");
    ASSERT_EQ(shots.size(), 3u);
    EXPECT_TRUE(allBlack(shots[0])) << "the difference of a scene from itself is black";
    expectSameImage(shots[1], direct({}), "K: the solution scene's image");
    EXPECT_TRUE(allBlack(shots[2])) << "stepped: both at draw 1";
    const std::string line = "difference from scene particles: 0 of " + std::to_string(kWidth * kHeight) +
                             " pixels differ (identical)";
    EXPECT_EQ(last_notes_, std::vector<std::string>{line});
    EXPECT_EQ(std::count(last_messages_.begin(), last_messages_.end(), line), 1)
        << "printed when the figures change: the same for the whole frame and draw 1";
    EXPECT_TRUE(last_solved_);
}

TEST_F(ViewerTest, ReferenceSolutionIsTheReferencePipelinesRender) {
    solution_ = "reference";
    // K, then J (from K straight to the difference), then stepped to draw 2's second particle.
    const std::vector<ImageRgba8> shots = run("K S J S N ] ] S K S");
    ASSERT_EQ(shots.size(), 4u);
    const auto reference = [](const Context::StepLimit& limit) {
        return direct(limit, "particles", std::nullopt, kWidth, kHeight, {.reference = true});
    };
    const RenderTarget fast = direct({}), exact = reference({});
    expectSameImage(shots[0], exact, "K: a reference-mode render of the scene, bit for bit");
    EXPECT_EQ(shots[1].pixels, differenceImage(fast.toRgba8(), exact.toRgba8(), kWidth, kHeight));
    EXPECT_EQ(shots[2].pixels,
              differenceImage(direct({2, 2}).toRgba8(), reference({2, 2}).toRgba8(), kWidth, kHeight));
    expectSameImage(shots[3], reference({2, 2}), "K at draw 2, primitive 2");
    // The count the HUD gives is a direct count of the pixels in which the two renders differ.
    size_t differing = 0;
    const uint8_t *a = fast.rgba8(), *b = exact.rgba8();
    for (size_t i = 0; i < size_t(kWidth) * kHeight; ++i)
        differing += !std::equal(a + 4 * i, a + 4 * i + 4, b + 4 * i);
    const std::vector<std::string> expected = describeDifference(
        compareImages({fast.toRgba8(), kWidth, kHeight}, {exact.toRgba8(), kWidth, kHeight}),
        "the reference pipeline");
    ASSERT_FALSE(expected.empty());
    EXPECT_TRUE(expected[0].starts_with(
        "difference from the reference pipeline: " + std::to_string(differing) + " of "))
        << expected[0];
    EXPECT_TRUE(said(last_messages_, expected[0])) << "the whole frame's difference is printed";
    // The solution is rendered only for K and J.
    run("S");
    EXPECT_FALSE(last_solved_);
    run("K K S");
    EXPECT_TRUE(last_solved_) << "K K shows the frame K asked for";
}

// raster view <lab>: K and J compare with the lab's solution without being told to.
TEST_F(ViewerTest, LabIsComparedWithItsSolution) {
    const std::vector<ImageRgba8> shots = run("J S K S", "billboards");
    ASSERT_EQ(shots.size(), 2u);
    const RenderTarget lab = direct({}, "billboards"), solution = direct({}, "billboards@solution");
    EXPECT_EQ(shots[0].pixels, differenceImage(lab.toRgba8(), solution.toRgba8(), kWidth, kHeight));
    expectSameImage(shots[1], solution, "K: the lab's solution");
    EXPECT_TRUE(last_solved_);
    const std::vector<std::string> lines = describeDifference(
        compareImages({lab.toRgba8(), kWidth, kHeight}, {solution.toRgba8(), kWidth, kHeight}),
        "scene billboards@solution");
    ASSERT_FALSE(lines.empty());
    EXPECT_TRUE(said(last_messages_, lines[0])) << lines[0];
}

// The status lines as the window shows them, read back from the window (--screenshot-window) with
// J's three lines of difference on a lab: at 640 pixels wide (small text) and 960 (large text,
// where the difference's first line is too long for one row), with and without the help (H).
TEST_F(ViewerTest, StatusLinesFitTheWindow) {
    for (const auto& [width, height] : {std::pair{640, 360}, std::pair{960, 540}}) {
        const std::string size = std::to_string(width) + "x" + std::to_string(height);
        ViewerOptions o = options("J S H S", "billboards");
        o.sceneOptions.width = uint32_t(width), o.sceneOptions.height = uint32_t(height);
        o.screenshotWindow = true;
        Viewer viewer(o);
        viewer.run();
        ASSERT_EQ(viewer.screenshots().size(), 2u) << size;
        std::vector<ImageRgba8> windows;
        for (const std::string& shot : viewer.screenshots())
            windows.push_back(readImageRgba8(shot.substr(0, shot.size() - 4) + "-window.png"));
        ASSERT_EQ(windows[0].width, uint32_t(width)) << size;
        ASSERT_EQ(windows[0].height, uint32_t(height)) << size;

        // Every line complete: the notes of J among the lines, the rows those lines unwrapped.
        const std::vector<std::string>& lines = viewer.statusLines();
        const std::vector<std::string>& rows = viewer.statusRows();
        ASSERT_EQ(viewer.viewNotes().size(), 3u) << size;
        EXPECT_TRUE(viewer.viewNotes()[0].starts_with("difference from scene billboards@solution: "))
            << viewer.viewNotes()[0];
        ASSERT_GE(lines.size(), 5u);
        EXPECT_TRUE(std::equal(viewer.viewNotes().begin(), viewer.viewNotes().end(), lines.end() - 3))
            << size;
        std::vector<std::string> unwrapped;
        for (const std::string& row : rows) {
            if (row.starts_with(kContinuationIndent) && !unwrapped.empty())
                unwrapped.back() += " " + row.substr(kContinuationIndent.size());
            else
                unwrapped.push_back(row);
        }
        EXPECT_EQ(unwrapped, lines) << size;
        if (width == 960) {
            EXPECT_GT(rows.size(), lines.size()) << "the difference's first line wraps";
        }

        // The pixels: the HUD's text is white (the difference view has none), the help's yellow.
        const int scale = overlayScale(width);
        const int text_right = width - kPanelMargin - kPanelPadding * scale;  // the text stays left of it
        const auto colour_at = [&](const ImageRgba8& image, int x, int y) {
            const uint8_t* p = &image.pixels[4 * (size_t(y) * image.width + size_t(x))];
            return Rgb{p[0], p[1], p[2]};
        };
        const Rgb white{255, 255, 255}, help_yellow{255, 240, 160};
        // Per row: the rightmost white pixel, -1 for none. Per shot: the text past the margins.
        const int top = kPanelMargin + kPanelPadding * scale, row_height = kPanelLineHeight * scale;
        std::vector<int> rightmost(rows.size(), -1);
        for (size_t shot = 0; shot < 2; ++shot) {
            int help_pixels = 0, outside = 0, below = 0;
            std::string first;  // where the first pixel outside or below is
            for (int y = 0; y < height; ++y)
                for (int x = 0; x < width; ++x) {
                    const Rgb c = colour_at(windows[shot], x, y);
                    if (c != white && c != help_yellow) continue;
                    help_pixels += c == help_yellow;
                    const int row = (y - top) / row_height;
                    const bool out = x >= text_right || y >= height - kPanelMargin,
                               low = c == white && (y < top || row >= int(rows.size()));
                    if ((out || low) && outside + below == 0)
                        first = std::to_string(x) + "," + std::to_string(y);
                    outside += out, below += low;
                    if (c == white && !low && shot == 0)
                        rightmost[size_t(row)] = std::max(rightmost[size_t(row)], x);
                }
            EXPECT_EQ(outside, 0) << "text pixels past the margins, the first at " << first << ", " << size
                                  << (shot ? " with the help" : "");
            EXPECT_EQ(below, 0) << "status text outside its rows, the first at " << first << ", " << size;
            EXPECT_EQ(help_pixels > 0, shot == 1) << size << " shot " << shot;
        }
        // Each row's last glyph drawn where the font's widths put it: the row is there, all of it.
        for (size_t r = 0; r < rows.size(); ++r) {
            const std::string& row = rows[r];
            ASSERT_FALSE(row.empty());
            const int last_glyph =
                kPanelMargin + (kPanelPadding + textWidth(row.substr(0, row.size() - 1))) * scale;
            EXPECT_GE(rightmost[r], last_glyph) << "row " << r << " '" << row << "', " << size;
            EXPECT_LT(rightmost[r], kPanelMargin + (kPanelPadding + textWidth(row)) * scale)
                << "row " << r << " '" << row << "', " << size;
        }
    }
}

TEST_F(ViewerTest, SolutionKeysWithoutASolutionSaySo) {
    const std::vector<ImageRgba8> shots = run("K S K J");
    ASSERT_EQ(shots.size(), 1u);
    expectSameImage(shots[0], direct({}), "K without a solution shows the frame");
    EXPECT_EQ(std::count(last_messages_.begin(), last_messages_.end(), std::string(kNoSolution)), 2);
    EXPECT_EQ(last_notes_, std::vector<std::string>{kNoSolution});
    EXPECT_FALSE(last_solved_);
}

TEST_F(ViewerTest, PngSolutionsAndTheirSize) {
    std::filesystem::create_directories(dir_);
    const RenderTarget draw1 = direct({1});
    solution_ = (dir_ / "draw1.png").string();
    draw1.savePng(solution_);
    const std::vector<ImageRgba8> shots = run("N J S 0 S K S click:160,90");
    ASSERT_EQ(shots.size(), 3u);
    EXPECT_TRUE(allBlack(shots[0])) << "draw 1 against its own PNG";
    EXPECT_EQ(shots[1].pixels, differenceImage(direct({}).toRgba8(), draw1.toRgba8(), kWidth, kHeight));
    expectSameImage(shots[2], draw1, "K: the PNG");
    EXPECT_FALSE(last_solved_) << "a PNG needs no render";
    const RenderTarget whole = direct({});
    const uint8_t* p = draw1.rgba8() + 4 * (size_t(90) * kWidth + 160);
    const uint8_t* q = whole.rgba8() + 4 * (size_t(90) * kWidth + 160);
    int largest = 0;
    for (int c = 0; c < 4; ++c) largest = std::max(largest, std::abs(int(p[c]) - int(q[c])));
    EXPECT_GT(largest, 0) << "a particle is in front of the occluder there";
    EXPECT_TRUE(said(last_messages_, "solution pixel 160,90: rgba " + std::to_string(p[0]) + " " +
                                         std::to_string(p[1]) + " " + std::to_string(p[2]) + " " +
                                         std::to_string(p[3]) + ", largest difference " +
                                         std::to_string(largest) + "/255"));
    // Another size: said, not compared; K shows it scaled.
    const RenderTarget small = direct({1}, "particles", std::nullopt, 32, 18);
    solution_ = (dir_ / "small.png").string();
    small.savePng(solution_);
    const std::vector<ImageRgba8> sized = run("J S K S");
    ASSERT_EQ(sized.size(), 2u);
    expectSameImage(sized[0], direct({}), "J: the frame, nothing to compare");
    EXPECT_EQ(sized[1].pixels, scaleNearest(small.toRgba8(), 32, 18, kWidth, kHeight));
    ASSERT_EQ(last_notes_.size(), 1u);
    EXPECT_NE(last_notes_[0].find("small.png is 32x18, the frame 320x180"), std::string::npos)
        << last_notes_[0];
    EXPECT_NE(last_notes_[0].find("--size 32x18"), std::string::npos) << last_notes_[0];
    // A PNG that is not there fails before a window opens, naming it.
    solution_ = (dir_ / "missing.png").string();
    try {
        Viewer viewer(options("K"));
        ADD_FAILURE() << "a missing PNG was accepted";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::BadFile);
        EXPECT_NE(std::string(e.what()).find("missing.png"), std::string::npos) << e.what();
    }
    solution_ = "nonesuch";
    expectInvalidArgument([&] { Viewer viewer(options("K")); }, {"unknown --solution 'nonesuch'"});
}

}  // namespace
}  // namespace raster::tools

// The march panel of a media scene's pixel: L rises from 0 to the march's L (the samples' added
// radiance), T falls from 1 to the march's T, s runs from the box's entry to its exit; scenes
// without a medium have no march.
TEST(MarchPlot, FollowsThePixelsMarchFromEntryToExit) {
    raster::SceneOptions options;
    options.width = 160, options.height = 90;
    const auto media = raster::makeScene("media", options);
    const std::optional<raster::PixelMarch> march = media->pixelMarch(80, 45, 160, 90);
    ASSERT_TRUE(march.has_value());
    ASSERT_GT(march->samples.size(), 10u);
    const raster::tools::MarchPlot plot = raster::tools::marchPlot(*march);
    ASSERT_EQ(plot.radiance.size(), march->samples.size() + 2);
    ASSERT_EQ(plot.transmittance.size(), plot.radiance.size());
    EXPECT_EQ(plot.radiance.front(), glm::vec2(march->t0, 0.0f));
    EXPECT_EQ(plot.transmittance.front(), glm::vec2(march->t0, 1.0f));
    const float mean_l = (march->radiance.r + march->radiance.g + march->radiance.b) / 3.0f;
    EXPECT_NEAR(plot.radiance.back().y, mean_l, 1e-5f * mean_l);
    EXPECT_EQ(plot.transmittance.back(), glm::vec2(march->t1, march->transmittance));
    for (size_t i = 1; i < plot.radiance.size(); ++i) {
        EXPECT_GE(plot.radiance[i].x, plot.radiance[i - 1].x) << i;
        EXPECT_GE(plot.radiance[i].y, plot.radiance[i - 1].y) << i;
        EXPECT_LE(plot.transmittance[i].y, plot.transmittance[i - 1].y * (1.0f + 1e-5f)) << i;
        EXPECT_LE(plot.radiance[i].y, plot.lMax) << i;
    }
    EXPECT_LT(march->transmittance, 0.5f);
    EXPECT_NE(plot.caption.find(std::to_string(march->samples.size()) + " samples"), std::string::npos);
    EXPECT_FALSE(raster::makeScene("fog", options)->pixelMarch(80, 45, 160, 90).has_value());
}
