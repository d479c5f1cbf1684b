!> The `prescribed_motion` key of a case: regions of grid nodes moved at a prescribed
!> velocity (a rigid footing, a loading plate, a pile, a retaining wall pushed or pulled).
!>
!> Each region is a box of the domain that moves with its own velocity: at time t its corners
!> are min + v F(t), max + v F(t), F the integral of its time function (the displacement of
!> the region). Every node inside the box that the material reaches moves at v f(t) along
!> the held `components` (all by default; only the vertical one for a smooth footing, whose
!> nodes slide freely sideways). The force the region applies on the material over each step
!> (the impulse that holds those components / dt) is its reaction, written to history.csv
!> with the region's displacement, and its work enters the energy balance as load work.
module mpm_case_motion
    use mpm_kinds, only: wp
    use mpm_error, only: error_type
    use mpm_strings, only: int_text, fmt_vector, fmt_real
    use mpm_case_cursor, only: cursor_type
    use mpm_case_domain, only: domain_section_type
    use mpm_case_loads, only: time_function_type, read_time_function, time_function_text, &
        read_box
    implicit none
    private
    public :: motion_spec_type, read_motions, motion_keys, motion_line

    character(len=*), parameter :: motion_keys(*) = [character(len=13) :: "name", "min", &
        "max", "velocity", "components", "time_function"]
        !! keys of one region
    character(len=*), parameter :: axis_names = "xyz"
        !! names of the components

    !> One region of `prescribed_motion`.
    type :: motion_spec_type
        character(len=:), allocatable :: name
            !! name (default "motion<i>"): the history.csv columns reaction_<name>_x, ...
        real(wp) :: xmin(3) = 0.0_wp, xmax(3) = 0.0_wp
            !! its box at the start [m]
        real(wp) :: velocity(3) = 0.0_wp
            !! its velocity at factor 1 [m/s]
        logical :: held(3) = .false.
            !! the velocity components it holds
        type(time_function_type) :: time
            !! its time function
    end type motion_spec_type

contains

    !> `prescribed_motion`: an optional array of regions, each checked against the domain;
    !> two regions may not share a node at the start.
    subroutine read_motions(root, dim, domain, motions, error)
        type(cursor_type), intent(in) :: root
            !! top-level object
        integer, intent(in) :: dim
            !! number of space dimensions
        type(domain_section_type), intent(in) :: domain
            !! the grid
        type(motion_spec_type), allocatable, intent(out) :: motions(:)
            !! the regions, in file order
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        type(cursor_type) :: list, item
        integer :: i, j, lo(dim), hi(dim)

        if (.not. root%has("prescribed_motion")) then
            allocate (motions(0))
            return
        end if
        call root%get_list("prescribed_motion", "region", list, error)
        if (allocated(error)) return
        allocate (motions(list%size()))
        do i = 1, size(motions)
            call list%named_item(i, motion_keys, "motion", item, motions(i)%name, error)
            if (allocated(error)) return
            if (verify(motions(i)%name, "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ" &
                //"0123456789_-") > 0) then
                call item%fail(error, item%key_path("name")//' = "'//motions(i)%name//'" ' &
                    //"names columns of history.csv: letters, digits, '_' and '-' only")
                return
            end if
            do j = 1, i - 1
                if (motions(j)%name == motions(i)%name) then
                    call item%fail(error, item%key_path("name")//' = "'//motions(i)%name &
                        //'" is already the name of prescribed_motion['//int_text(j) &
                        //"]; names must be unique")
                    return
                end if
            end do
            call read_box(item, dim, domain, motions(i)%xmin, motions(i)%xmax, error)
            if (allocated(error)) return
            lo = ceiling((motions(i)%xmin(1:dim) - domain%origin(1:dim))/domain%dx - 1.0e-9_wp)
            hi = floor((motions(i)%xmax(1:dim) - domain%origin(1:dim))/domain%dx + 1.0e-9_wp)
            if (any(hi < lo)) then
                call item%fail(error, item%path//": its box min = " &
                    //fmt_vector(motions(i)%xmin(1:dim))//" m, max = " &
                    //fmt_vector(motions(i)%xmax(1:dim))//" m holds no node of the grid " &
                    //"(spacing "//fmt_real(domain%dx)//" m from the origin); a region moves " &
                    //"the nodes inside its box")
                return
            end if
            call item%get_vector("velocity", dim, motions(i)%velocity, error, required=.true., &
                unit="m/s")
            if (allocated(error)) return
            call read_components(item, dim, motions(i)%held, error)
            if (allocated(error)) return
            call read_time_function(item, motions(i)%time, error)
            if (allocated(error)) return
            if (motions(i)%time%factor(0.0_wp) /= 0.0_wp .and. &
                any(motions(i)%held(1:dim) .and. motions(i)%velocity(1:dim) /= 0.0_wp)) then
                call item%fail(error, item%path//" starts at its full velocity at t = 0: a " &
                    //"sudden start is an impact, whose energy the balance does not book (the " &
                    //"guard stops the run); start it from rest with a time_function whose " &
                    //'factor is 0 at t = 0, e.g. {"type": "ramp", "duration": 0.1}')
                return
            end if
            do j = 1, i - 1
                if (all(motions(j)%xmin(1:dim) <= motions(i)%xmax(1:dim) .and. &
                    motions(i)%xmin(1:dim) <= motions(j)%xmax(1:dim))) then
                    call item%fail(error, item%path//": its box min = " &
                        //fmt_vector(motions(i)%xmin(1:dim))//" m, max = " &
                        //fmt_vector(motions(i)%xmax(1:dim))//" m overlaps that of " &
                        //"prescribed_motion["//int_text(j)//"]; a node moves with one region")
                    return
                end if
            end do
        end do
    end subroutine read_motions

    !> `components`: the axes whose velocity a region holds (all when absent).
    subroutine read_components(item, dim, held, error)
        type(cursor_type), intent(in) :: item
            !! the region's object
        integer, intent(in) :: dim
            !! number of space dimensions
        logical, intent(out) :: held(3)
            !! the held components
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        type(cursor_type) :: list, name
        character(len=:), allocatable :: text, allowed
        integer :: k, axis
        logical :: given

        held = .false.
        held(1:dim) = .true.
        if (.not. item%has("components")) return
        allowed = merge('"x", "y"     ', '"x", "y", "z"', dim == 2)
        call item%get_typed("components", "array", "an array of axis names ("//trim(allowed) &
            //")", list, given, error)
        if (allocated(error)) return
        held = .false.
        if (list%size() == 0) then
            call item%fail(error, item%key_path("components")//" is empty; give the axes " &
                //"whose velocity the region holds, among "//trim(allowed))
            return
        end if
        do k = 1, list%size()
            name = list%item(k)
            text = name%text()
            axis = 0
            if (len(text) == 1) axis = index(axis_names(1:dim), text)
            if (axis == 0) then
                call item%fail(error, name%path//" = "//name%found()//" is not an axis; " &
                    //"allowed: "//trim(allowed))
                return
            end if
            if (held(axis)) then
                call item%fail(error, name%path//' = "'//text//'" is given twice')
                return
            end if
            held(axis) = .true.
        end do
    end subroutine read_components

    !> One line of the --check summary for a region.
    pure function motion_line(motion, dim) result(line)
        type(motion_spec_type), intent(in) :: motion
            !! the region
        integer, intent(in) :: dim
            !! number of space dimensions
        character(len=:), allocatable :: line

        integer :: d

        line = motion%name//": nodes of "//fmt_vector(motion%xmin(1:dim))//" - " &
            //fmt_vector(motion%xmax(1:dim))//" m at "//fmt_vector(motion%velocity(1:dim)) &
            //" m/s along"
        do d = 1, dim
            if (motion%held(d)) line = line//" "//axis_names(d:d)
        end do
        line = line//", "//time_function_text(motion%time)
    end function motion_line

end module mpm_case_motion
