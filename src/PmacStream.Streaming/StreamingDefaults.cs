namespace PmacStream.Streaming;

/// <summary>
/// The defaults of how a session feeds the rotary buffer. They live with the layer that uses them; the job service's
/// <c>RunSettings</c> starts from them.
/// </summary>
public static class StreamingDefaults
{
    /// <summary>Rotary buffer words (<c>&amp;1 DEFINE ROT</c>): room for the executing chunk's rest and the next whole chunk.</summary>
    public const int BufferWords = 16_000;

    /// <summary>The download window opens at line 600 of a 1000-line chunk.</summary>
    public const double WindowStart = 0.6;

    /// <summary>The download window closes at line 700 of a 1000-line chunk.</summary>
    public const double WindowEnd = 0.7;

    /// <summary>Words the session keeps free in the rotary buffer against the splitter's estimate.</summary>
    public const int BufferMarginWords = 64;

    /// <summary>
    /// WRITEBUFFER packets the <c>full</c> strategy keeps in flight over Ethernet (1: each waits for its reply). Several
    /// in flight let TCP recover a lost reply from the next reply's duplicate ACKs within a round trip, where a lone
    /// request waits for the controller's retransmission timeout (200 ms or more): issue 28's 3 % loss runs.
    /// </summary>
    public const int PacketsInFlight = 8;

    /// <summary>
    /// Most rotary-buffer words (the controller's count) one pipelined batch of the <c>full</c> strategy carries: about
    /// 2,300 bench blocks, so the batch's 2,000-line limit binds first and a refill after a stall is as large as with one
    /// packet in flight (8,000 words left 0.57 s as the least lead in issue 28's loaded runs, against 1.0 s).
    /// </summary>
    public const int WordsInFlight = 16_000;

    /// <summary>Words of the controller's free memory (<c>SIZE</c>) a buffer sized from it leaves for PLCs and programs loaded later.</summary>
    public const int MemoryReserveWords = 1_024;

    /// <summary>The timer period (timer1's interval).</summary>
    public static readonly TimeSpan TickPeriod = TimeSpan.FromMilliseconds(50);
}
