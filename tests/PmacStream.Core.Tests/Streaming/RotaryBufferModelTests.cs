using PmacStream.Preparation;
using PmacStream.Streaming;

namespace PmacStream.Core.Tests.Streaming;

public class RotaryBufferModelTests
{
    private static ProgramLine Move(int line, int words = 5) => new($"M0=={line} X{line}", line, true, words, 0);

    private static ProgramLine Plain(int words = 2) => new("M08", 0, false, words, 0);

    [Fact]
    public void Accepted_lines_take_words_and_the_free_room_is_size_less_margin_less_occupancy()
    {
        var model = new RotaryBufferModel(bufferWords: 100, safetyWords: 10);
        model.FreeWords.Should().Be(90);

        model.Accept(Move(10));
        model.Accept(Plain());
        model.Accept(Move(12));

        model.Lines.Should().Be(3);
        model.Words.Should().Be(12);
        model.FreeWords.Should().Be(78);
        model.MovesAhead.Should().Be(2);
        model.LinesSent.Should().Be(3);
        model.LastSentLine.Should().Be(12);
    }

    [Fact]
    public void Free_room_never_goes_below_zero()
    {
        var model = new RotaryBufferModel(bufferWords: 20, safetyWords: 10);
        model.Accept(Move(1, words: 15));
        model.FreeWords.Should().Be(0);
    }

    [Fact]
    public void Reaching_a_move_frees_every_line_before_it_with_the_non_motion_lines_of_the_move_before()
    {
        var model = new RotaryBufferModel(100, 0);
        model.Accept(Move(10));
        model.Accept(Plain());
        model.Accept(Move(12));

        model.Reached(10);
        model.Lines.Should().Be(3, "the move M0 names is executing: its line and those after it may still be in use");

        model.Reached(12);
        model.Lines.Should().Be(1);
        model.Words.Should().Be(5);
        model.MovesAhead.Should().Be(1);
        model.MovesReached.Should().Be(1);
    }

    [Fact]
    public void PR_drops_the_oldest_lines_beyond_the_lines_it_reports()
    {
        var model = new RotaryBufferModel(100, 0);
        model.Accept(Move(1));
        model.Accept(Plain());
        model.Accept(Move(3, words: 7));

        model.LinesAhead(1);

        model.Lines.Should().Be(1);
        model.Words.Should().Be(7);
        model.MovesAhead.Should().Be(1);
    }

    [Fact]
    public void A_drained_buffer_is_empty_and_sending_continues_after_the_move_M0_names()
    {
        var model = new RotaryBufferModel(100, 0);
        model.Accept(Move(1));
        model.Accept(Move(2));

        model.Drained(1);

        model.Lines.Should().Be(0);
        model.Words.Should().Be(0);
        model.LastSentLine.Should().Be(1);
        model.MovesSent.Should().Be(2, "what was sent stays counted");
        model.MovesReached.Should().Be(2);
    }

    [Fact]
    public void A_resumed_job_charges_the_lines_PR_reports_at_the_chunks_average_words_as_moves_after_M0()
    {
        var model = new RotaryBufferModel(1000, 0);
        var chunk = new ChunkInfo(1, "p_0001.pmc", 1, 100, BlockCount: 40, MotionBlockCount: 30, ByteSize: 0, EstimatedWords: 210, Sha256: "");

        model.Resumed(linesAhead: 4, chunk, trackedLine: 50, lastSentLine: 60);

        model.Words.Should().Be(4 * 6, "210 words over 40 blocks is 5.25, rounded up");
        model.MovesAhead.Should().Be(4);
        model.LastSentLine.Should().Be(60);
        model.Reached(51);
        model.Lines.Should().Be(4);
        model.Reached(52);
        model.Lines.Should().Be(0);
    }

    [Fact]
    public void Reset_forgets_the_lines_and_the_counts_of_an_earlier_load()
    {
        var model = new RotaryBufferModel(100, 0);
        model.Accept(Move(1));
        model.Reset();

        model.Lines.Should().Be(0);
        model.Words.Should().Be(0);
        model.MovesSent.Should().Be(0);
        model.LinesSent.Should().Be(0);
        model.LastSentLine.Should().Be(0);
    }

    [Fact]
    public void A_chunk_larger_than_the_room_is_refused_and_the_line_probe_counts_a_word_a_block()
    {
        using var temp = new TestFolder("fit");
        var program = FakeSplit.Write(temp.Path, FakeSplit.Program(100, 4), 100);
        var words = program.Manifest.Chunks[0].EstimatedWords;
        var blocks = program.Manifest.Chunks[0].BlockCount;
        program.UseLineProbe(null);

        new RotaryBufferModel(words + 10, 10).EnsureChunksFit(program);
        FluentActions.Invoking(() => new RotaryBufferModel(words + 9, 10).EnsureChunksFit(program))
            .Should().Throw<InvalidOperationException>().WithMessage("chunk 1 (prog_0001.pmc) needs about*");

        program.UseLineProbe("P501");
        FluentActions.Invoking(() => new RotaryBufferModel(words + 10, 10).EnsureChunksFit(program)).Should().Throw<InvalidOperationException>();
        new RotaryBufferModel(words + blocks + 10, 10).EnsureChunksFit(program);
    }
}
