!> A factor of time (`time_function` of loads and prescribed motions) and the CSV tables of
!> times and values it and the seismic records of the faces read.
!>
!> `constant` (the default), `ramp` (0 until `start`, linear to 1 over `duration`, then 1) or
!> `table` (times and factors of a CSV `file`, linear between its rows, the first and last
!> factor outside them).
module mpm_time_function
    use mpm_kinds, only: wp
    use mpm_error, only: error_type
    use mpm_strings, only: int_text, fmt_real
    use mpm_case_cursor, only: cursor_type
    implicit none
    private
    public :: time_function_type, read_time_function, time_function_text, time_function_keys
    public :: time_constant, time_ramp, time_table, time_function_names, read_table

    integer, parameter :: time_constant = 1, time_ramp = 2, time_table = 3
        !! time function types
    character(len=*), parameter :: time_function_names(3) = [character(len=8) :: "constant", &
        "ramp", "table"]
        !! name of each time function type in the case file
    character(len=*), parameter :: time_function_keys(*) = [character(len=8) :: "type", &
        "start", "duration", "file"]
        !! keys of a time function
    integer, parameter :: max_table_rows = 1000000
        !! rows of a table accepted

    !> A factor of time that scales a load or a prescribed velocity.
    type :: time_function_type
        integer :: type = time_constant
            !! time_constant, time_ramp or time_table
        real(wp) :: start = 0.0_wp
            !! a ramp's start [s]
        real(wp) :: duration = 0.0_wp
            !! a ramp's rise time [s]
        character(len=:), allocatable :: file
            !! a table's CSV file
        real(wp), allocatable :: times(:)
            !! a table's times, increasing [s]
        real(wp), allocatable :: factors(:)
            !! a table's factors [-]
    contains
        !> The factor at a time.
        procedure :: factor => time_factor
        !> The integral of the factor from 0 to a time.
        procedure :: integral => time_integral
    end type time_function_type

contains

    !> The factor of a time function at time t.
    pure real(wp) function time_factor(tf, t)
        class(time_function_type), intent(in) :: tf
            !! the time function
        real(wp), intent(in) :: t
            !! time [s]

        integer :: lo, hi, mid

        select case (tf%type)
        case (time_ramp)
            time_factor = min(1.0_wp, max(0.0_wp, (t - tf%start)/tf%duration))
        case (time_table)
            if (t <= tf%times(1)) then
                time_factor = tf%factors(1)
            else if (t >= tf%times(size(tf%times))) then
                time_factor = tf%factors(size(tf%factors))
            else
                lo = 1
                hi = size(tf%times)
                do while (hi - lo > 1)
                    mid = (lo + hi)/2
                    if (tf%times(mid) <= t) then
                        lo = mid
                    else
                        hi = mid
                    end if
                end do
                time_factor = tf%factors(lo) + (tf%factors(hi) - tf%factors(lo))* &
                    (t - tf%times(lo))/(tf%times(hi) - tf%times(lo))
            end if
        case default
            time_factor = 1.0_wp
        end select
    end function time_factor

    !> The integral of a time function's factor from 0 to t [s] (the displacement of a
    !> prescribed velocity per unit of it): exact for the piecewise-linear factors.
    pure real(wp) function time_integral(tf, t)
        class(time_function_type), intent(in) :: tf
            !! the time function
        real(wp), intent(in) :: t
            !! time [s], >= 0

        integer :: k
        real(wp) :: t0, t1

        select case (tf%type)
        case (time_ramp)
            if (t <= tf%start) then
                time_integral = 0.0_wp
            else if (t <= tf%start + tf%duration) then
                time_integral = 0.5_wp*(t - tf%start)**2/tf%duration
            else
                time_integral = 0.5_wp*tf%duration + (t - tf%start - tf%duration)
            end if
        case (time_table)
            ! before the first row and after the last the factor is constant
            time_integral = tf%factors(1)*max(0.0_wp, min(t, tf%times(1)))
            do k = 1, size(tf%times) - 1
                t0 = max(0.0_wp, tf%times(k))
                t1 = min(t, tf%times(k + 1))
                if (t1 <= t0) cycle
                time_integral = time_integral + 0.5_wp*(tf%factor(t0) + tf%factor(t1))*(t1 - t0)
            end do
            if (t > tf%times(size(tf%times))) time_integral = time_integral + &
                tf%factors(size(tf%factors))*(t - max(0.0_wp, tf%times(size(tf%times))))
        case default
            time_integral = t
        end select
    end function time_integral

    !> `time_function` of a load (constant when absent).
    subroutine read_time_function(item, tf, error)
        type(cursor_type), intent(in) :: item
            !! the load's object
        type(time_function_type), intent(inout) :: tf
            !! its time function
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        type(cursor_type) :: cur
        logical :: found
        integer :: k

        call item%get_section("time_function", time_function_keys, cur, error, found=found)
        if (allocated(error) .or. .not. found) return
        call cur%get_choice("type", time_function_names, [time_constant, time_ramp, &
            time_table], tf%type, error, required=.true.)
        if (allocated(error)) return
        do k = 2, 4
            if (.not. cur%has(trim(time_function_keys(k)))) cycle
            if ((k <= 3 .and. tf%type /= time_ramp) .or. (k == 4 .and. tf%type /= time_table)) &
                then
                call cur%fail(error, cur%key_path(trim(time_function_keys(k)))//" only " &
                    //'applies to a time function of type "'//trim(merge("ramp ", "table", &
                    k <= 3))//'"; remove it')
                return
            end if
        end do
        select case (tf%type)
        case (time_ramp)
            call cur%get_real("start", tf%start, error, at_least=0.0_wp, unit="s")
            if (allocated(error)) return
            call cur%get_real("duration", tf%duration, error, above=0.0_wp, required=.true., &
                unit="s")
        case (time_table)
            tf%file = ""
            call cur%get_path("file", 0, tf%file, error, required=.true.)
            if (allocated(error)) return
            call read_time_table(cur, tf, error)
        case default
            continue
        end select
    end subroutine read_time_function

    !> The rows "time, factor" of a time table's CSV file (an optional header line first;
    !> times strictly increasing).
    subroutine read_time_table(cur, tf, error)
        type(cursor_type), intent(in) :: cur
            !! the time function's object
        type(time_function_type), intent(inout) :: tf
            !! the table, file set
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        call read_table(cur, "file", tf%file, "factor", tf%times, tf%factors, error)
    end subroutine read_time_table

    !> The rows "time, value" of a CSV file named by key `key` of an object (an optional
    !> header line first; times strictly increasing, values finite; at most 1e6 rows): a
    !> time table's factors, a seismic record's accelerations or velocities. Each error names
    !> the key, the file and the line.
    subroutine read_table(cur, key, file, what, times, values, error)
        type(cursor_type), intent(in) :: cur
            !! the object holding the key
        character(len=*), intent(in) :: key
            !! the key that names the file ("file")
        character(len=*), intent(in) :: file
            !! the file, as the key gives it
        character(len=*), intent(in) :: what
            !! the value's name in messages ("factor", "acceleration")
        real(wp), allocatable, intent(out) :: times(:)
            !! the times [s]
        real(wp), allocatable, intent(out) :: values(:)
            !! the values
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        character(len=1024) :: line
        character(len=256) :: msg
        character(len=:), allocatable :: where
        real(wp) :: t, f
        real(wp), allocatable :: tt(:), ff(:)
        integer :: unit, ios, n, row
        logical :: exists

        where = cur%key_path(key)//' = "'//file//'"'
        inquire (file=file, exist=exists)
        if (.not. exists) then
            call cur%fail(error, where//": no such file (a CSV file of rows 'time, "//what &
                //"'; a relative path is taken from the current working directory)")
            return
        end if
        open (newunit=unit, file=file, status="old", action="read", iostat=ios, iomsg=msg)
        if (ios /= 0) then
            call cur%fail(error, where//": cannot be opened for reading: "//trim(msg))
            return
        end if
        allocate (tt(16), ff(16))
        n = 0
        row = 0
        do
            read (unit, "(a)", iostat=ios, iomsg=msg) line
            if (ios /= 0) exit
            row = row + 1
            if (len_trim(line) == 0) cycle
            read (line, *, iostat=ios, iomsg=msg) t, f
            if (ios /= 0) then
                if (row == 1) cycle
                call cur%fail(error, where//": line "//int_text(row)//" is not two numbers " &
                    //"'time, "//what//"': '"//trim(line)//"'")
                exit
            end if
            if (.not. (abs(t) <= huge(t) .and. abs(f) <= huge(f))) then
                call cur%fail(error, where//": line "//int_text(row)//" holds a value that " &
                    //"is not finite")
                exit
            end if
            if (n > 0) then
                if (t <= tt(n)) then
                    call cur%fail(error, where//": the times must increase; line " &
                        //int_text(row)//" has time "//fmt_real(t, 6)//" s after " &
                        //fmt_real(tt(n), 6)//" s")
                    exit
                end if
            end if
            if (n == max_table_rows) then
                call cur%fail(error, where//": more than "//int_text(max_table_rows)//" rows")
                exit
            end if
            if (n == size(tt)) then
                tt = [tt, tt]
                ff = [ff, ff]
            end if
            n = n + 1
            tt(n) = t
            ff(n) = f
        end do
        close (unit)
        if (allocated(error)) return
        if (n == 0) then
            call cur%fail(error, where//": holds no row 'time, "//what//"'")
            return
        end if
        times = tt(1:n)
        values = ff(1:n)
    end subroutine read_table

    !> A time function in words, for --check: "constant", "ramp from 0 s over 1 s", ...
    pure function time_function_text(tf) result(text)
        type(time_function_type), intent(in) :: tf
            !! the time function
        character(len=:), allocatable :: text

        select case (tf%type)
        case (time_ramp)
            text = "ramp from "//fmt_real(tf%start)//" s over "//fmt_real(tf%duration)//" s"
        case (time_table)
            text = "table "//tf%file//" ("//int_text(size(tf%times))//" rows)"
        case default
            text = "constant"
        end select
    end function time_function_text

end module mpm_time_function
