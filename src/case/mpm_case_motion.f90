!> The `prescribed_motion` key of a case: regions of grid nodes moved at a prescribed
!> velocity (a loading plate, a wall pushed or pulled), and rigid bodies pushed at one (a
!> footing, a pile).
!>
!> A box region moves with its own velocity: at time t its corners are min + v F(t),
!> max + v F(t), F the integral of its time function (the displacement of the region).
!> Every node inside the box that the material reaches moves at v f(t) along the held
!> `components` (all by default; only the vertical one for a smooth footing, whose nodes
!> slide freely sideways). A rigid body (`"rigid"`: the name of a material of type "rigid")
!> is the set of nodes whose cell its particles fill to a fifth in each step: they move at v f(t) along the held
!> components, and the body moves freely along the others. The force a region applies on
!> the material over each step (the impulse that holds those components / dt) is its
!> reaction, written to history.csv with the region's displacement, and its work enters the
!> energy balance as load work. Every rigid material the case does not name here is a free
!> rigid body: an entry of its own, named after it, that holds no component.
module mpm_case_motion
    use mpm_kinds, only: wp
    use mpm_error, only: error_type
    use mpm_strings, only: int_text, fmt_vector, fmt_real
    use mpm_case_cursor, only: cursor_type
    use mpm_case_domain, only: domain_section_type
    use mpm_case_loads, only: read_box
    use mpm_time_function, only: time_function_type, read_time_function, time_function_text
    use mpm_case_materials, only: material_spec_type, material_index, material_list
    implicit none
    private
    public :: motion_spec_type, read_motions, motion_keys, motion_line

    character(len=*), parameter :: motion_keys(*) = [character(len=13) :: "name", "min", &
        "max", "rigid", "velocity", "components", "time_function"]
        !! keys of one region
    character(len=*), parameter :: axis_names = "xyz"
        !! names of the components
    character(len=*), parameter :: name_characters = "abcdefghijklmnopqrstuvwxyz" &
        //"ABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-"
        !! the characters of a name of history.csv columns

    !> One region of `prescribed_motion`.
    type :: motion_spec_type
        character(len=:), allocatable :: name
            !! name (default "motion<i>"): the history.csv columns reaction_<name>_x, ...
        integer :: rigid = 0
            !! the rigid material whose particles are the body (0: a box region)
        real(wp) :: xmin(3) = 0.0_wp, xmax(3) = 0.0_wp
            !! its box at the start [m] (a box region)
        real(wp) :: velocity(3) = 0.0_wp
            !! its velocity at factor 1 [m/s]
        logical :: held(3) = .false.
            !! the velocity components it holds
        type(time_function_type) :: time
            !! its time function
    end type motion_spec_type

contains

    !> `prescribed_motion`: an optional array of regions, each checked against the domain;
    !> two regions may not share a node at the start, two entries may not push the same
    !> rigid body. Then a free rigid body for each rigid material no entry names.
    subroutine read_motions(root, dim, domain, materials, used, motions, error)
        type(cursor_type), intent(in) :: root
            !! top-level object
        integer, intent(in) :: dim
            !! number of space dimensions
        type(domain_section_type), intent(in) :: domain
            !! the grid
        type(material_spec_type), intent(in) :: materials(:)
            !! the materials
        logical, intent(in) :: used(:)
            !! whether some body (or particle list) holds particles of each material
        type(motion_spec_type), allocatable, intent(out) :: motions(:)
            !! the regions, in file order
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        type(cursor_type) :: list, item
        integer :: i, j, m
        character(len=:), allocatable :: rigid

        allocate (motions(0))
        if (root%has("prescribed_motion")) then
            call root%get_list("prescribed_motion", "region", list, error)
            if (allocated(error)) return
            deallocate (motions)
            allocate (motions(list%size()))
        end if
        do i = 1, size(motions)
            call list%named_item(i, motion_keys, "motion", item, motions(i)%name, error)
            if (allocated(error)) return
            if (item%has("rigid")) then
                call read_rigid(item, materials, used, motions(i), error)
                if (allocated(error)) return
                do j = 1, i - 1
                    if (motions(j)%rigid /= motions(i)%rigid) cycle
                    call item%fail(error, item%key_path("rigid")//' = "' &
                        //materials(motions(i)%rigid)%name//'" is pushed by ' &
                        //"prescribed_motion["//int_text(j)//"] already; a rigid body " &
                        //"moves with one entry")
                    return
                end do
            end if
            if (verify(motions(i)%name, name_characters) > 0) then
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
            if (motions(i)%rigid == 0) then
                call read_region_box(item, dim, domain, motions, i, error)
                if (allocated(error)) return
            end if
            call read_velocity(item, dim, motions(i), error)
            if (allocated(error)) return
        end do
        ! the free rigid bodies
        do m = 1, size(materials)
            if (.not. allocated(materials(m)%law)) cycle
            if (.not. materials(m)%law%rigid()) cycle
            if (any(motions%rigid == m)) cycle
            rigid = materials(m)%name
            if (.not. used(m)) then
                call root%fail(error, "materials["//int_text(m)//'] "'//rigid//'" is a ' &
                    //"rigid body that no body of the case fills; give it a body or remove it")
                return
            end if
            if (verify(rigid, name_characters) > 0 .or. any([(motions(i)%name == rigid, &
                i=1, size(motions))])) then
                call root%fail(error, "materials["//int_text(m)//'] "'//rigid//'" is a ' &
                    //"free rigid body, whose name names its columns of history.csv: use " &
                    //"letters, digits, '_' and '-' only, and a name no entry of " &
                    //"prescribed_motion has")
                return
            end if
            motions = [motions, motion_spec_type(name=rigid, rigid=m)]
        end do
    end subroutine read_motions

    !> The box of region i (`min`, `max`): inside the domain, holding a node, overlapping no
    !> box region before it.
    subroutine read_region_box(item, dim, domain, motions, i, error)
        type(cursor_type), intent(in) :: item
            !! the entry
        integer, intent(in) :: dim
            !! number of space dimensions
        type(domain_section_type), intent(in) :: domain
            !! the grid
        type(motion_spec_type), intent(inout) :: motions(:)
            !! the entries (i is read)
        integer, intent(in) :: i
            !! the entry
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        integer :: j, lo(dim), hi(dim)

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
        do j = 1, i - 1
            if (motions(j)%rigid > 0) cycle
            if (all(motions(j)%xmin(1:dim) <= motions(i)%xmax(1:dim) .and. &
                motions(i)%xmin(1:dim) <= motions(j)%xmax(1:dim))) then
                call item%fail(error, item%path//": its box min = " &
                    //fmt_vector(motions(i)%xmin(1:dim))//" m, max = " &
                    //fmt_vector(motions(i)%xmax(1:dim))//" m overlaps that of " &
                    //"prescribed_motion["//int_text(j)//"]; a node moves with one region")
                return
            end if
        end do
    end subroutine read_region_box

    !> `rigid`: the rigid material whose body the entry pushes (its name is the entry's
    !> default name); the entry has no box.
    subroutine read_rigid(item, materials, used, motion, error)
        type(cursor_type), intent(in) :: item
            !! the entry
        type(material_spec_type), intent(in) :: materials(:)
            !! the materials
        logical, intent(in) :: used(:)
            !! whether some body holds particles of each material
        type(motion_spec_type), intent(inout) :: motion
            !! the entry read
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        character(len=:), allocatable :: name
        integer :: m

        name = ""
        call item%get_string("rigid", name, error, required=.true.)
        if (allocated(error)) return
        m = material_index(materials, name)
        if (m == 0) then
            call item%fail(error, item%key_path("rigid")//' = "'//name//'" is not a ' &
                //"material of this case; the materials are: "//material_list(materials))
            return
        end if
        if (.not. allocated(materials(m)%law)) then
            call item%fail(error, item%key_path("rigid")//' = "'//name//'" has no type')
            return
        end if
        if (.not. materials(m)%law%rigid()) then
            call item%fail(error, item%key_path("rigid")//' = "'//name//'" is a material ' &
                //'of type "'//materials(m)%type//'"; a rigid body is a material of type ' &
                //'"rigid"')
            return
        end if
        if (.not. used(m)) then
            call item%fail(error, item%key_path("rigid")//' = "'//name//'": no body of the ' &
                //"case holds particles of it; give the rigid body a body")
            return
        end if
        if (item%has("min") .or. item%has("max")) then
            call item%fail(error, item%path//" pushes the rigid body "//'"'//name//'", ' &
                //"whose nodes are those its particles fill: remove min and max (a box " &
                //"region is an entry without rigid)")
            return
        end if
        motion%rigid = m
        if (.not. item%has("name")) motion%name = name
    end subroutine read_rigid

    !> `velocity`, `components` and `time_function` of an entry, and its start from rest.
    subroutine read_velocity(item, dim, motion, error)
        type(cursor_type), intent(in) :: item
            !! the entry
        integer, intent(in) :: dim
            !! number of space dimensions
        type(motion_spec_type), intent(inout) :: motion
            !! the entry read
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        call item%get_vector("velocity", dim, motion%velocity, error, required=.true., &
            unit="m/s")
        if (allocated(error)) return
        call read_components(item, dim, motion%held, error)
        if (allocated(error)) return
        call read_time_function(item, motion%time, error)
        if (allocated(error)) return
        if (motion%time%factor(0.0_wp) /= 0.0_wp .and. &
            any(motion%held(1:dim) .and. motion%velocity(1:dim) /= 0.0_wp)) then
            call item%fail(error, item%path//" starts at its full velocity at t = 0: a " &
                //"sudden start is an impact, whose energy the balance does not book (the " &
                //"guard stops the run); start it from rest with a time_function whose " &
                //'factor is 0 at t = 0, e.g. {"type": "ramp", "duration": 0.1}')
        end if
    end subroutine read_velocity

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

        if (motion%rigid > 0) then
            line = motion%name//": rigid body"
            if (.not. any(motion%held(1:dim))) then
                line = line//", free"
                return
            end if
        else
            line = motion%name//": nodes of "//fmt_vector(motion%xmin(1:dim))//" - " &
                //fmt_vector(motion%xmax(1:dim))//" m"
        end if
        line = line//" at "//fmt_vector(motion%velocity(1:dim))//" m/s along"
        do d = 1, dim
            if (motion%held(d)) line = line//" "//axis_names(d:d)
        end do
        if (motion%rigid > 0 .and. .not. all(motion%held(1:dim))) line = line//" (free along " &
            //"the others)"
        line = line//", "//time_function_text(motion%time)
    end function motion_line

end module mpm_case_motion
