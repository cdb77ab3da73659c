using System.Text;

namespace PmacStream.Sim.Tests.Engine;

/// <summary>Command in, exact bytes out, over the in-process port (I3=2, I6=1 unless a test changes them).</summary>
public class TranscriptTests
{
    [Theory]
    [InlineData("", "<ACK>")]
    [InlineData("P500=80", "<ACK>")]
    [InlineData("P500=80 P500", "80<CR><ACK>")]
    [InlineData("p500=12.5 p500", "12.5<CR><ACK>")]
    [InlineData("P1=3 P2=P1*2+1 P2", "7<CR><ACK>")]
    [InlineData("P1..3=7 P1..3", "7<CR>7<CR>7<CR><ACK>")]
    [InlineData("Q10=4 Q10", "4<CR><ACK>")]
    [InlineData("M5=-2 M5", "-2<CR><ACK>")]
    [InlineData("I3 I6", "2<CR>1<CR><ACK>")]
    [InlineData("I113 I114", "0<CR>0<CR><ACK>")]
    [InlineData("i6=1 i3=2 ver", "1.947<CR><ACK>")]
    [InlineData("VERSION", "1.947<CR><ACK>")]
    [InlineData("VER", "1.947<CR><ACK>")]
    [InlineData("TYPE", "TURBO2<CR><ACK>")]
    [InlineData("CID", "602413<CR><ACK>")]
    [InlineData("I16 I17", "5<CR>10<CR><ACK>")]
    [InlineData("FOO", "<BEL>ERR003<CR>")]
    [InlineData("P1 FOO", "0<CR><BEL>ERR003<CR>")]
    [InlineData("LINEAR", "<BEL>ERR005<CR>")]
    [InlineData("X10", "<BEL>ERR005<CR>")]
    [InlineData("M0==5", "<BEL>ERR003<CR>")]
    [InlineData("CLEAR", "<BEL>ERR005<CR>")]
    [InlineData("&1B7R", "<BEL>ERR015<CR>")]
    [InlineData("DEL GAT", "<ACK>")]
    [InlineData("DELETE GATHER", "<ACK>")]
    [InlineData("DEFINE GATHER", "<ACK>")]
    [InlineData("&1 DEF ROT 1000", "<ACK>")]
    [InlineData("&1 DEFINE ROT 1000 PR", "0<CR><ACK>")]
    [InlineData("&1 DELETE ROT", "<ACK>")]
    [InlineData("&1 DEL ROT", "<ACK>")]
    [InlineData("%", "100<CR><ACK>")]
    [InlineData("&1??", "A80000020000000000<CR><ACK>")]
    [InlineData("#1?", "88200007C401<CR><ACK>")]
    [InlineData("P1=2 &1 P1", "2<CR><ACK>")]
    [InlineData("P1=7 %50 P1", "7<CR><ACK>")]
    [InlineData("P1=7 % 4 P1", "3<CR><ACK>")]
    [InlineData("P1=6&3 P1", "2<CR><ACK>")]
    [InlineData("???", "000000000000<CR><ACK>")]
    [InlineData("#2P", "0<CR><ACK>")]
    [InlineData("M800->Y:$078800,0 M800->", "Y:$078800,0<CR><ACK>")]
    [InlineData("M1000->Y:$078800,0,8 M1000->", "Y:$078800,0,8<CR><ACK>")]
    [InlineData("M1001->* M1001->", "*<CR><ACK>")]
    [InlineData("#1->1000X #1->", "1000X<CR><ACK>")]
    [InlineData("P1=$1F P1", "31<CR><ACK>")]
    [InlineData("P1=5 ; comment P1=6", "<ACK>")]
    [InlineData("ENA PLC 1", "<ACK>")]
    [InlineData("DIS PLC 1", "<ACK>")]
    [InlineData("SAVE", "<ACK>")]
    public void Online_commands(string command, string expected)
    {
        using var h = new SimHarness();
        h.Send(command).Should().Be(expected);
    }

    [Fact]
    public void Bytes_above_127_are_an_illegal_character()
    {
        using var h = new SimHarness();
        h.Send("P1=\u00e9").Should().Be("<BEL>ERR004<CR>");
        h.Sim.Counters.Errors.Should().Be(1);
    }

    [Fact]
    public void Raw_bytes_are_exactly_the_controllers()
    {
        using var h = new SimHarness();
        h.Port.Execute("P1=2 P1").Should().Equal(Encoding.ASCII.GetBytes("2\r\x06"));
        h.Port.Execute("XYZZY").Should().Equal(Encoding.ASCII.GetBytes("\x07" + "ERR003\r"));
    }

    [Fact]
    public void I3_and_I6_change_the_framing_per_port()
    {
        using var h = new SimHarness();
        var other = h.Sim.OpenPort("other");
        h.Send("I6=0").Should().Be("<ACK>");
        h.Send("FOO").Should().Be("<BEL>");
        h.Send(other, "FOO").Should().Be("<BEL>ERR003<CR>", "each port has its own I6");
        h.Send("I3=0 P7=1").Should().Be(string.Empty);
        h.Send("P7").Should().Be("1<CR>");
        h.Send("I3=1").Should().Be("<LF>");
        h.Send("P7").Should().Be("1<CR><LF>");
        h.Send("I3=3").Should().Be("<ACK>");
        h.Send("P7").Should().Be("<LF>1<CR><ACK>");
        h.Send("I3=2 I6=1 I3").Should().Be("2<CR><ACK>");
        h.Send(other, "I3").Should().Be("2<CR><ACK>");
    }

    [Fact]
    public void Reset_restores_power_on_state()
    {
        using var h = new SimHarness();
        h.Ok("P1=5 I3=2 &1 DEFINE ROT 100 %50");
        h.Download("OPEN PROG 3 CLEAR", "X1", "CLOSE");
        h.Send("$$$").Should().Be("<ACK>");
        h.Send("P1").Should().Be("0<CR><ACK>");
        h.Send("LIST PROG 3").Should().Be("X1<CR><ACK>", "program buffers survive a reset");
        h.Send("&1 PR").Should().Be("0<CR><ACK>");
        h.Send("$$$***").Should().Be("<ACK>");
        h.Send("LIST PROG 3").Should().Be("<BEL>ERR003<CR>");
    }

    [Fact]
    public void List_prog_returns_the_stored_lines()
    {
        using var h = new SimHarness();
        h.Download("OPEN PROG 1000 CLEAR", "n0 rapid   ret", "N1000 LINEAR RET", "CLOSE");
        h.Send("LIST PROG 1000").Should().Be("N0 RAPID RET<CR>N1000 LINEAR RET<CR><ACK>");
        h.Download("OPEN PROG 1000 CLEAR", "N0 RAPID RET", "CLOSE");
        h.Send("LIST PROG 1000").Should().Be("N0 RAPID RET<CR><ACK>", "CLEAR empties the buffer");
    }

    [Fact]
    public void Close_of_an_unbalanced_program_is_a_structural_error()
    {
        using var h = new SimHarness();
        h.Download("OPEN PROG 5 CLEAR", "IF (P1=1)", "X1");
        h.Send("CLOSE").Should().Be("<BEL>ERR009<CR>");
        h.Send("OPEN PROG 5 CLEAR ENDIF CLOSE").Should().Be("<BEL>ERR009<CR>");
    }

    [Fact]
    public void Control_characters_answer_without_terminator_ack()
    {
        using var h = new SimHarness();
        h.Ok("&1 OPEN ROT LINEAR ABS F600 X10 Y-2 CLOSE B0 R");
        h.Sim.RunUntilIdle();
        Encoding.ASCII.GetString(h.Port.Control('\x10')).Should().Be("10 -2 0 0 0 0 0 0\r");
        Encoding.ASCII.GetString(h.Port.Control('P')).Should().Be("10 -2 0 0 0 0 0 0\r");
        h.Port.Control('\x18').Should().BeEmpty();
        Encoding.ASCII.GetString(h.Port.Control('\x07')).Should().Be("000000000000\r");
    }

    [Fact]
    public void Status_words_follow_running_mode_and_full_bit()
    {
        using var h = new SimHarness();
        h.Ok("&1 B0 OPEN ROT RAPID LINEAR F60");
        for (var i = 1; i <= 10; i++)
        {
            h.Ok($"X{i}");
        }

        h.Ok("CLOSE");
        h.Ok("PR").Should().Be("11");
        // Second word: bit 16 rotary full (>= I17 lines ahead), bit 17 in position; nothing calculated yet.
        h.Ok("??").Should().Be("A80000030000000000");
        h.Ok("R");
        var status = h.Ok("??");
        status[..6].Should().Be("A80011", "running, continuous motion request");
        status.Substring(6, 6).Should().Be("210000", "moves in stack, full bit still set (7 ahead is not below I16), LINEAR");
        h.Ok("PR").Should().Be("7");
        h.Advance(2.5);
        h.Ok("PR").Should().Be("5");
        h.Ok("??").Substring(6, 6).Should().Be("210000", "5 ahead is not below I16=5");
        h.Advance(1);
        h.Ok("PR").Should().Be("4");
        h.Ok("??").Substring(6, 6).Should().Be("200000", "below I16: full bit cleared");
        h.Sim.RunUntilIdle();
        h.Ok("PR").Should().Be("0");
        h.Ok("??").Should().Be("A80011020000000000", "a rotary program waits for more lines: still running, in position");
    }
}
